//! PNG charts with plotters, drawn with the shipped DejaVu Sans font (so the
//! images are the same on every machine, with no system font library).

use std::path::Path;
use std::sync::OnceLock;

use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::{FontStyle, register_font};

use super::LabError;

/// The font, shipped in `assets/fonts/` with its licence.
static FONT: &[u8] = include_bytes!("../../../assets/fonts/DejaVuSans.ttf");

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

fn frame(path: &Path) -> Result<DrawingArea<BitMapBackend<'_>, Shift>, LabError> {
    font()?;
    let root = BitMapBackend::new(path, SIZE).into_drawing_area();
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
    let root = frame(path)?;
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
    let root = frame(path)?;
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
