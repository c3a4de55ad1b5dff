//! PNG charts with plotters, drawn with the shipped DejaVu Sans font (so the
//! images are the same on every machine, with no system font library).

use std::path::Path;
use std::sync::OnceLock;

use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::{FontStyle, register_font};

use super::LabError;

/// The font, shipped in `engine/fonts/` with its licence.
static FONT: &[u8] = include_bytes!("../../../engine/fonts/DejaVuSans.ttf");

fn font() -> Result<(), LabError> {
    static REGISTERED: OnceLock<bool> = OnceLock::new();
    let ok = *REGISTERED.get_or_init(|| register_font("sans-serif", FontStyle::Normal, FONT).is_ok());
    if ok { Ok(()) } else { Err(LabError::Font) }
}

/// One line on a chart.
#[derive(Clone, Debug)]
pub struct Series {
    /// Legend label.
    pub label: String,
    /// Points; non-finite and (on log axes) non-positive ones are left out.
    pub points: Vec<(f64, f64)>,
    /// Drawn thicker (to single out, say, the symplectic methods).
    pub bold: bool,
}

/// Chart size in pixels.
pub const SIZE: (u32, u32) = (1400, 800);

/// Width of the legend panel on the right.
const LEGEND_WIDTH: u32 = 300;

/// Twenty distinct, dark-enough colours (after the tab20 and Dark2 sets), so
/// every method's line is readable on white.
const COLOURS: [(u8, u8, u8); 20] = [
    (31, 119, 180),
    (255, 127, 14),
    (44, 160, 44),
    (214, 39, 40),
    (148, 103, 189),
    (140, 86, 75),
    (227, 119, 194),
    (90, 90, 90),
    (188, 189, 34),
    (23, 190, 207),
    (27, 158, 119),
    (217, 95, 2),
    (117, 112, 179),
    (231, 41, 138),
    (102, 166, 30),
    (166, 118, 29),
    (0, 0, 128),
    (128, 0, 0),
    (0, 100, 100),
    (0, 0, 0),
];

/// The colour of series `k`.
fn colour(k: usize) -> RGBColor {
    let (r, g, b) = COLOURS[k % COLOURS.len()];
    RGBColor(r, g, b)
}

/// Tick labels like `1e-6`.
fn exponent_label(v: &f64) -> String {
    format!("{v:.0e}")
}

/// A chart at `path` that could not be drawn: [`LabError::Plot`], with
/// plotters' error as its source.
fn error(path: &Path, e: impl std::error::Error + Send + Sync + 'static) -> LabError {
    LabError::Plot {
        path: path.to_path_buf(),
        source: Box::new(e),
    }
}

fn range(values: impl Iterator<Item = f64>, log: bool) -> (f64, f64) {
    let (lo, hi) = values
        .filter(|v| v.is_finite() && (!log || *v > 0.0))
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| (lo.min(v), hi.max(v)));
    if !lo.is_finite() {
        return (1e-3, 1.0);
    }
    if log {
        (lo / 2.0, hi * 2.0)
    } else {
        let pad = (hi - lo).max(1e-9) * 0.05;
        (lo - pad, hi + pad)
    }
}

fn frame(path: &Path, size: (u32, u32)) -> Result<DrawingArea<BitMapBackend<'_>, Shift>, LabError> {
    font()?;
    let root = BitMapBackend::new(path, size).into_drawing_area();
    root.fill(&WHITE).map_err(|e| error(path, e))?;
    Ok(root)
}

/// A chart of `series`, with a log-scale y axis and a log or linear x axis,
/// and the legend in a panel to the right of the plot.
///
/// # Errors
/// [`LabError::Plot`], naming the file, when it cannot be drawn or written.
pub fn lines(
    path: &Path,
    title: &str,
    x_label: &str,
    y_label: &str,
    log_x: bool,
    series: &[Series],
) -> Result<(), LabError> {
    let root = frame(path, SIZE)?;
    let (plot, legend) = root.split_horizontally(SIZE.0 - LEGEND_WIDTH);
    let xs = series.iter().flat_map(|s| s.points.iter().map(|p| p.0));
    let ys = series.iter().flat_map(|s| s.points.iter().map(|p| p.1));
    let (x0, x1) = range(xs, log_x);
    let (y0, y1) = range(ys, true);
    let mut builder = ChartBuilder::on(&plot);
    builder
        .caption(title, ("sans-serif", 22))
        .margin(16)
        .x_label_area_size(50)
        .y_label_area_size(80);
    let keep = |p: &&(f64, f64)| p.0.is_finite() && p.1.is_finite() && p.1 > 0.0 && (!log_x || p.0 > 0.0);
    macro_rules! draw {
        ($chart:expr, $x_format:expr) => {{
            let mut chart = $chart.map_err(|e| error(path, e))?;
            chart
                .configure_mesh()
                .x_desc(x_label)
                .y_desc(y_label)
                .x_label_formatter($x_format)
                .y_label_formatter(&exponent_label)
                .label_style(("sans-serif", 16))
                .draw()
                .map_err(|e| error(path, e))?;
            for (k, s) in series.iter().enumerate() {
                let style = colour(k).stroke_width(if s.bold { 3 } else { 1 });
                let points: Vec<(f64, f64)> = s.points.iter().filter(keep).copied().collect();
                chart
                    .draw_series(LineSeries::new(points.clone(), style))
                    .map_err(|e| error(path, e))?;
                // Markers only where the points are few (measured runs).
                if points.len() <= 12 {
                    chart
                        .draw_series(points.into_iter().map(|p| Circle::new(p, 3, colour(k).filled())))
                        .map_err(|e| error(path, e))?;
                }
            }
        }};
    }
    if log_x {
        draw!(
            builder.build_cartesian_2d((x0..x1).log_scale(), (y0..y1).log_scale()),
            &exponent_label
        );
    } else {
        draw!(
            builder.build_cartesian_2d(x0..x1, (y0..y1).log_scale()),
            &|v: &f64| format!("{v}")
        );
    }
    for (k, s) in series.iter().enumerate() {
        let y = 60 + 26 * k as i32;
        let style = colour(k).stroke_width(if s.bold { 3 } else { 2 });
        legend
            .draw(&PathElement::new(vec![(10, y), (40, y)], style))
            .and_then(|()| legend.draw(&Text::new(s.label.as_str(), (48, y - 8), ("sans-serif", 15))))
            .map_err(|e| error(path, e))?;
    }
    root.present().map_err(|e| error(path, e))
}

/// Measured (filled) and theoretical (hollow) stability limits, one row per
/// method; infinite limits are drawn at the right edge, marked "any h".
///
/// # Errors
/// [`LabError::Plot`], naming the file, when it cannot be drawn or written.
pub fn limits(path: &Path, title: &str, x_label: &str, rows: &[(&str, f64, Option<f64>)]) -> Result<(), LabError> {
    let root = frame(path, SIZE)?;
    let right = 4.0;
    let clip = |v: f64| if v.is_finite() { v.min(right) } else { right };
    let names: Vec<&str> = rows.iter().map(|r| r.0).collect();
    let n = rows.len();
    // Row k is drawn at y = n - 1 - k, so the first method is at the top.
    let at = |k: usize| (n - 1 - k) as f64;
    let mut chart = ChartBuilder::on(&root)
        .caption(title, ("sans-serif", 24))
        .margin(16)
        .x_label_area_size(50)
        .y_label_area_size(230)
        .build_cartesian_2d(0f64..right + 0.3, -0.5f64..n as f64 - 0.5)
        .map_err(|e| error(path, e))?;
    chart
        .configure_mesh()
        .y_labels(n)
        .y_label_formatter(&|y| {
            let k = y.round();
            if (y - k).abs() < 1e-6 && k >= 0.0 && (k as usize) < n {
                names[n - 1 - k as usize].to_owned()
            } else {
                String::new()
            }
        })
        .x_label_formatter(&|x| {
            if *x >= right - 1e-9 {
                "any h".to_owned()
            } else {
                format!("{x:.1}")
            }
        })
        .x_desc(x_label)
        .label_style(("sans-serif", 16))
        .draw()
        .map_err(|e| error(path, e))?;
    chart
        .draw_series(
            rows.iter()
                .enumerate()
                .map(|(k, r)| Circle::new((clip(r.1), at(k)), 7, BLUE.filled())),
        )
        .map_err(|e| error(path, e))?
        .label("measured")
        .legend(|(x, y)| Circle::new((x + 10, y), 6, BLUE.filled()));
    chart
        .draw_series(
            rows.iter()
                .enumerate()
                .filter_map(|(k, r)| r.2.map(|t| Circle::new((clip(t), at(k)), 11, RED.stroke_width(2)))),
        )
        .map_err(|e| error(path, e))?
        .label("theory")
        .legend(|(x, y)| Circle::new((x + 10, y), 8, RED.stroke_width(2)));
    chart
        .configure_series_labels()
        .position(SeriesLabelPosition::MiddleRight)
        .label_font(("sans-serif", 16))
        .background_style(WHITE.mix(0.9))
        .border_style(BLACK)
        .draw()
        .map_err(|e| error(path, e))?;
    root.present().map_err(|e| error(path, e))
}

/// Size of a figure of panels side by side, in pixels.
pub const WIDE: (u32, u32) = (1900, 850);

/// Width of the legend panel of [`panels`].
const WIDE_LEGEND_WIDTH: u32 = 430;

/// Charts side by side sharing their axes' labels, one y range and one
/// legend: line `k` of every panel is drawn in colour `k` (dashed past the
/// twentieth, where the colours repeat) and named by `legend[k]`.
#[derive(Clone, Copy, Debug)]
pub struct Panels<'a> {
    /// The figure's title.
    pub title: &'a str,
    /// The x axis.
    pub x_label: &'a str,
    /// The y axis.
    pub y_label: &'a str,
    /// A log-scale y axis (non-positive points are left out).
    pub log_y: bool,
    /// The y range of every panel, lines leaving it cut at its edges;
    /// `None`: the range of all the data.
    pub y_range: Option<(f64, f64)>,
    /// Lines above the legend.
    pub legend_title: &'a [&'a str],
    /// The legend: a label and whether the line is drawn thicker, a line.
    pub legend: &'a [(String, bool)],
    /// The panels, left to right.
    pub panels: &'a [Panel],
}

/// One chart of [`Panels`].
#[derive(Clone, Debug)]
pub struct Panel {
    /// Its title.
    pub title: String,
    /// Its lines, in the legend's order (non-finite points are left out).
    pub lines: Vec<Vec<(f64, f64)>>,
}

/// `points` cut to `lo <= y <= hi`: the pieces inside, with the points
/// where the line crosses an edge.
fn clip(points: &[(f64, f64)], lo: f64, hi: f64) -> Vec<Vec<(f64, f64)>> {
    let inside = |p: (f64, f64)| (lo..=hi).contains(&p.1);
    let edge = |p: (f64, f64), q: (f64, f64), y: f64| (p.0 + (q.0 - p.0) * (y - p.1) / (q.1 - p.1), y);
    let mut pieces: Vec<Vec<(f64, f64)>> = Vec::new();
    let mut piece: Vec<(f64, f64)> = Vec::new();
    for (k, &q) in points.iter().enumerate() {
        let prev = k.checked_sub(1).map(|j| points[j]);
        match (prev, inside(q)) {
            (None, true) => piece.push(q),
            (None, false) => {}
            (Some(p), true) => {
                if !inside(p) {
                    piece.push(edge(p, q, if p.1 > hi { hi } else { lo }));
                }
                piece.push(q);
            }
            (Some(p), false) => {
                let far = if q.1 > hi { hi } else { lo };
                if inside(p) {
                    piece.push(edge(p, q, far));
                    pieces.push(core::mem::take(&mut piece));
                } else if (p.1 > hi) != (q.1 > hi) {
                    // Across the whole range in one segment.
                    let near = if p.1 > hi { hi } else { lo };
                    pieces.push(vec![edge(p, q, near), edge(p, q, far)]);
                }
            }
        }
    }
    if !piece.is_empty() {
        pieces.push(piece);
    }
    pieces.retain(|p| p.len() >= 2);
    pieces
}

/// Draws [`Panels`] at `path`, [`WIDE`] pixels, the legend on the right.
///
/// # Errors
/// [`LabError::Plot`], naming the file, when it cannot be drawn or written.
pub fn panels(path: &Path, figure: &Panels<'_>) -> Result<(), LabError> {
    let root = frame(path, WIDE)?;
    let body = root
        .titled(figure.title, ("sans-serif", 24))
        .map_err(|e| error(path, e))?;
    let (plots, legend) = body.split_horizontally(WIDE.0 - WIDE_LEGEND_WIDTH);
    let areas = plots.split_evenly((1, figure.panels.len().max(1)));
    let finite = |p: &&(f64, f64)| p.0.is_finite() && p.1.is_finite() && (!figure.log_y || p.1 > 0.0);
    let all = || {
        figure
            .panels
            .iter()
            .flat_map(|p| p.lines.iter().flatten())
            .filter(finite)
    };
    let (x0, x1) = range(all().map(|p| p.0), false);
    let (y0, y1) = figure
        .y_range
        .unwrap_or_else(|| range(all().map(|p| p.1), figure.log_y));
    let y_format = |v: &f64| {
        if figure.log_y {
            exponent_label(v)
        } else {
            format!("{v}")
        }
    };
    for (area, panel) in areas.iter().zip(figure.panels) {
        let mut builder = ChartBuilder::on(area);
        builder
            .caption(&panel.title, ("sans-serif", 20))
            .margin(16)
            .x_label_area_size(50)
            .y_label_area_size(80);
        macro_rules! draw {
            ($chart:expr) => {{
                let mut chart = $chart.map_err(|e| error(path, e))?;
                chart
                    .configure_mesh()
                    .x_desc(figure.x_label)
                    .y_desc(figure.y_label)
                    .x_label_formatter(&|v: &f64| format!("{v}"))
                    .y_label_formatter(&y_format)
                    .label_style(("sans-serif", 16))
                    .draw()
                    .map_err(|e| error(path, e))?;
                for (k, points) in panel.lines.iter().enumerate() {
                    let bold = figure.legend.get(k).is_some_and(|l| l.1);
                    let style = colour(k).stroke_width(if bold { 4 } else { 2 });
                    let points: Vec<(f64, f64)> = points.iter().filter(finite).copied().collect();
                    for piece in clip(&points, y0, y1) {
                        if k >= COLOURS.len() {
                            chart
                                .draw_series(DashedLineSeries::new(piece, 8, 5, style))
                                .map_err(|e| error(path, e))?;
                        } else {
                            chart
                                .draw_series(LineSeries::new(piece, style))
                                .map_err(|e| error(path, e))?;
                        }
                    }
                }
            }};
        }
        if figure.log_y {
            draw!(builder.build_cartesian_2d(x0..x1, (y0..y1).log_scale()));
        } else {
            draw!(builder.build_cartesian_2d(x0..x1, y0..y1));
        }
    }
    let mut y = 40;
    for line in figure.legend_title {
        legend
            .draw(&Text::new(*line, (10, y), ("sans-serif", 16)))
            .map_err(|e| error(path, e))?;
        y += 22;
    }
    y += 14;
    for (k, (label, bold)) in figure.legend.iter().enumerate() {
        let style = colour(k).stroke_width(if *bold { 4 } else { 2 });
        let sample = if k >= COLOURS.len() {
            vec![((10, y), (20, y)), ((28, y), (40, y))]
        } else {
            vec![((10, y), (40, y))]
        };
        for (a, b) in sample {
            legend
                .draw(&PathElement::new(vec![a, b], style))
                .map_err(|e| error(path, e))?;
        }
        legend
            .draw(&Text::new(label.as_str(), (48, y - 8), ("sans-serif", 15)))
            .map_err(|e| error(path, e))?;
        y += 26;
    }
    root.present().map_err(|e| error(path, e))
}

#[cfg(test)]
mod tests {
    use super::clip;

    #[test]
    fn lines_are_cut_where_they_cross_the_range() {
        let line = [(0.0, 0.0), (1.0, 2.0), (2.0, 4.0), (3.0, 2.0), (4.0, -2.0), (5.0, 2.0)];
        let pieces = clip(&line, 1.0, 3.0);
        assert_eq!(
            pieces,
            vec![
                vec![(0.5, 1.0), (1.0, 2.0), (1.5, 3.0)],
                vec![(2.5, 3.0), (3.0, 2.0), (3.25, 1.0)],
                vec![(4.75, 1.0), (5.0, 2.0)],
            ]
        );
        // Across the whole range within one segment.
        assert_eq!(
            clip(&[(0.0, 0.0), (1.0, 4.0)], 1.0, 3.0),
            vec![vec![(0.25, 1.0), (0.75, 3.0)]]
        );
        assert!(clip(&[(0.0, 5.0), (1.0, 6.0)], 1.0, 3.0).is_empty());
    }
}
