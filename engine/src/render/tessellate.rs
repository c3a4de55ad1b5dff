//! A game's shapes as triangles, by lyon: filled polygons of any shape
//! (concave, self-crossing, with holes: the even-odd rule, so a hole is a
//! hole whichever way it winds) and strokes of any width with joins and
//! caps, their curves flattened to within `tolerance` (the renderer's
//! callers pass a quarter of a pixel).

use glam::Vec2;
use lyon_tessellation::math::point;
use lyon_tessellation::path::Path;
use lyon_tessellation::{
    BuffersBuilder, FillOptions, FillRule, FillTessellator, FillVertex, LineCap, LineJoin, StrokeOptions,
    StrokeTessellator, StrokeVertex, VertexBuffers,
};

use super::stroke::{Cap, Join};

/// The path through each ring of points, each closed.
fn rings_path(rings: &[&[Vec2]], closed: bool) -> Path {
    let mut builder = Path::builder();
    for ring in rings {
        let Some((first, rest)) = ring.split_first() else {
            continue;
        };
        builder.begin(point(first.x, first.y));
        for p in rest {
            builder.line_to(point(p.x, p.y));
        }
        builder.end(closed);
    }
    builder.build()
}

fn triangles(buffers: &VertexBuffers<Vec2, u32>, out: &mut Vec<[Vec2; 3]>) {
    out.extend(
        buffers
            .indices
            .chunks_exact(3)
            .map(|t| [0, 1, 2].map(|k| buffers.vertices[t[k] as usize])),
    );
}

/// Appends the triangles filling `rings` (the first the outline, the
/// others holes) to `out`.
///
/// # Errors
/// lyon's message, for input it cannot fill.
pub(crate) fn fill(rings: &[&[Vec2]], tolerance: f32, out: &mut Vec<[Vec2; 3]>) -> Result<(), String> {
    let path = rings_path(rings, true);
    let mut buffers: VertexBuffers<Vec2, u32> = VertexBuffers::new();
    let options = FillOptions::default()
        .with_fill_rule(FillRule::EvenOdd)
        .with_tolerance(tolerance);
    FillTessellator::new()
        .tessellate_path(
            &path,
            &options,
            &mut BuffersBuilder::new(&mut buffers, |v: FillVertex| Vec2::new(v.position().x, v.position().y)),
        )
        .map_err(|e| format!("{e:?}"))?;
    triangles(&buffers, out);
    Ok(())
}

/// Appends the triangles of a stroke `width` wide along `points` (closed
/// back to the first if `closed`) to `out`.
///
/// # Errors
/// lyon's message, for input it cannot stroke.
pub(crate) fn stroke(
    points: &[Vec2],
    closed: bool,
    width: f32,
    join: Join,
    cap: Cap,
    tolerance: f32,
    out: &mut Vec<[Vec2; 3]>,
) -> Result<(), String> {
    let path = rings_path(&[points], closed);
    let mut buffers: VertexBuffers<Vec2, u32> = VertexBuffers::new();
    let options = StrokeOptions::default()
        .with_line_width(width)
        .with_tolerance(tolerance)
        .with_line_join(match join {
            Join::Miter => LineJoin::MiterClip,
            Join::Round => LineJoin::Round,
            Join::Bevel => LineJoin::Bevel,
        })
        .with_line_cap(match cap {
            Cap::Butt => LineCap::Butt,
            Cap::Round => LineCap::Round,
            Cap::Square => LineCap::Square,
        });
    StrokeTessellator::new()
        .tessellate_path(
            &path,
            &options,
            &mut BuffersBuilder::new(&mut buffers, |v: StrokeVertex| {
                Vec2::new(v.position().x, v.position().y)
            }),
        )
        .map_err(|e| format!("{e:?}"))?;
    triangles(&buffers, out);
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Twice the signed area of a triangle.
    fn area(t: &[Vec2; 3]) -> f32 {
        ((t[1] - t[0]).perp_dot(t[2] - t[0])).abs() * 0.5
    }

    #[test]
    fn concave_and_holed_polygons_fill_their_area_exactly() {
        // An L of three unit squares (concave).
        let l = [
            Vec2::ZERO,
            Vec2::new(2.0, 0.0),
            Vec2::new(2.0, 1.0),
            Vec2::new(1.0, 1.0),
            Vec2::new(1.0, 2.0),
            Vec2::new(0.0, 2.0),
        ];
        let mut out = Vec::new();
        fill(&[&l], 0.01, &mut out).expect("fills");
        let total: f32 = out.iter().map(area).sum();
        assert!((total - 3.0).abs() < 1e-5, "{total}");
        // The notch is not covered: no triangle holds (1.5, 1.5).
        let inside = |t: &[Vec2; 3], p: Vec2| {
            let s = |a: Vec2, b: Vec2| (b - a).perp_dot(p - a);
            let (d0, d1, d2) = (s(t[0], t[1]), s(t[1], t[2]), s(t[2], t[0]));
            (d0 >= 0.0 && d1 >= 0.0 && d2 >= 0.0) || (d0 <= 0.0 && d1 <= 0.0 && d2 <= 0.0)
        };
        assert!(!out.iter().any(|t| inside(t, Vec2::new(1.5, 1.5))));
        // A 4 x 4 square with a 2 x 2 hole, the hole wound either way.
        let square = [
            Vec2::ZERO,
            Vec2::new(4.0, 0.0),
            Vec2::new(4.0, 4.0),
            Vec2::new(0.0, 4.0),
        ];
        let hole = [
            Vec2::splat(1.0),
            Vec2::new(3.0, 1.0),
            Vec2::splat(3.0),
            Vec2::new(1.0, 3.0),
        ];
        let reversed: Vec<Vec2> = hole.iter().rev().copied().collect();
        for h in [&hole[..], &reversed[..]] {
            out.clear();
            fill(&[&square, h], 0.01, &mut out).expect("fills");
            let total: f32 = out.iter().map(area).sum();
            assert!((total - 12.0).abs() < 1e-4, "{total}");
            assert!(!out.iter().any(|t| inside(t, Vec2::splat(2.0))), "the hole is empty");
        }
    }

    #[test]
    fn a_stroke_covers_its_width_along_its_length() {
        // A straight stroke 0.5 wide and 4 long, flat ends: area 2.
        let mut out = Vec::new();
        stroke(
            &[Vec2::ZERO, Vec2::new(4.0, 0.0)],
            false,
            0.5,
            Join::Round,
            Cap::Butt,
            0.001,
            &mut out,
        )
        .expect("strokes");
        let total: f32 = out.iter().map(area).sum();
        assert!((total - 2.0).abs() < 1e-4, "{total}");
        // Square caps add half the width at each end.
        out.clear();
        stroke(
            &[Vec2::ZERO, Vec2::new(4.0, 0.0)],
            false,
            0.5,
            Join::Round,
            Cap::Square,
            0.001,
            &mut out,
        )
        .expect("strokes");
        let total: f32 = out.iter().map(area).sum();
        assert!((total - 2.25).abs() < 1e-4, "{total}");
    }
}
