//! The hierarchical grid, for spheres of mixed sizes. One cell size for all
//! would be set by the largest sphere, and a single radius-20 ball among
//! radius-0.05 grains put thousands of grains in each cell (a step 270
//! times slower, quadratic in the grains). So a sphere of radius `r`
//! belongs to level `l = floor(log2(r_max / r))` (up to [`LEVELS`], enough
//! for any two `f32` radii), whose cells have size `2 r_max / 2^l >= 2 r`;
//! all levels share one hash table keyed by (level, cell). A sphere looks
//! for partners in its own level (those later in the sorted order) and in
//! every coarser level in use (bigger spheres: their cell size covers the
//! contact distance `r_i + r_j`), so every touching pair is found once, and
//! the cost stays linear in the number of spheres times the number of
//! levels in use, whatever the ratio of the radii (two spheres of radius
//! 1e30 among grains of 0.045 add a level, not a quadratic term). Up to 24
//! levels the cells are placed in `f32`; a finer level places every sphere
//! in `f64`.

use super::SphereCollisions;
use super::cells::{NEIGHBOURS, cell_of, hash, neighbour};
use super::narrow::Window;
use crate::colliders::ContactColumns;
use crate::math;

/// Levels of the hierarchical grid: enough for any two `f32` radii (the
/// largest over the smallest positive is below `2^278`), so no mix of sizes
/// puts small spheres in cells made for big ones (two grains of radius
/// 1e30 among 100 000 of radius 0.045, each in a cell of its own size, cost
/// what the grains alone cost, plus a level).
pub(super) const LEVELS: u32 = 280;

/// Levels below this are placed in `f32` (the common case, kept bit for bit
/// as it always was); a world using a finer one places every sphere in
/// `f64`, whose range holds the cells of any `f32` sphere.
pub(super) const F32_LEVELS: u16 = 24;

/// `2^l`, exactly (`l` below 1024).
pub(super) fn power_of_two(l: u16) -> f64 {
    f64::from_bits((1023 + u64::from(l)) << 52)
}

impl SphereCollisions {
    pub(super) fn resolve_levels(&mut self, c: &ContactColumns<'_>, max_radius: f32) -> bool {
        let n = c.position.len();
        let inv_top = 1.0 / (2.0 * max_radius);
        // Level of each sphere, and its cell at that level (cells 2^l times
        // finer than the top level's). A radius of 0 touches nothing: finest.
        // The level of a radius (below 2^128 times smaller, in f32 as it
        // always was; past it, in f64, whose range holds the ratio).
        let level_of = |r: f32| -> Option<u16> {
            let ratio = max_radius / r;
            if ratio.is_finite() {
                Some(math::log2(ratio).floor() as u16)
            } else if r > 0.0 {
                Some(math::log2(f64::from(max_radius) / f64::from(r)).floor() as u16)
            } else {
                None
            }
        };
        // A radius of 0 touches only bigger spheres: the finest level in
        // use (or, as always, the 24th).
        let finest = c
            .radius
            .iter()
            .filter_map(|&r| level_of(r))
            .fold(F32_LEVELS - 1, u16::max)
            .min(LEVELS as u16 - 1);
        self.level.clear();
        self.level.extend(
            c.radius
                .iter()
                .map(|&r| level_of(r).map_or(finest, |l| l.min(LEVELS as u16 - 1))),
        );
        let mut used = [0u64; (LEVELS as usize).div_ceil(64)];
        for &l in &self.level {
            used[usize::from(l / 64)] |= 1 << (l % 64);
        }
        self.used_levels.clear();
        self.used_levels.extend(
            (0..LEVELS as u16)
                .rev()
                .filter(|l| used[usize::from(l / 64)] & (1 << (l % 64)) != 0),
        );
        self.cell.clear();
        if finest < F32_LEVELS && inv_top.is_normal() {
            let scale = |l: u16| inv_top * (1u32 << l) as f32;
            self.cell
                .extend(c.position.iter().zip(&self.level).map(|(x, &l)| cell_of(*x, scale(l))));
        } else {
            // Every cell from the same f64 product, scaled by exact powers
            // of two, so a coarser level's cell is a shift of a finer one's.
            let inv_top = 0.5 / f64::from(max_radius);
            self.cell.extend(
                c.position
                    .iter()
                    .zip(&self.level)
                    .map(|(x, &l)| (x.as_dvec3() * inv_top * power_of_two(l)).floor().as_i64vec3()),
            );
        }
        let buckets = (2 * n).next_power_of_two();
        let mask = (buckets - 1) as u32;
        self.key.clear();
        self.key
            .extend(self.cell.iter().zip(&self.level).map(|(cell, &l)| hash(*cell, l, mask)));
        if !self.sort_and_gather(buckets, c) {
            return false;
        }
        let (sorted_cell, starts, sorted_level, used_levels) =
            (&self.sorted_cell, &self.starts, &self.sorted_level, &self.used_levels);
        let mut w = Window::whole(
            [&mut self.x, &mut self.y, &mut self.z],
            &mut self.velocity,
            &self.radius,
            &self.inverse_mass,
            self.material,
            self.recording.then_some(&mut self.pairs),
        );
        for i in 0..n {
            let own = sorted_level[i];
            // Own level, then every coarser non-empty one, whose cells are
            // 2^(own - level) of this level's: the cell there is a shift.
            for &level in used_levels.iter().filter(|&&l| l <= own) {
                // Past 63 levels the shift leaves the sign: 0 or -1.
                let home = sorted_cell[i] >> i64::from((own - level).min(63));
                for offset in NEIGHBOURS {
                    let Some(cell) = neighbour(home, offset) else {
                        continue;
                    };
                    let b = hash(cell, level, mask) as usize;
                    let (first, end) = (starts[b] as usize, starts[b + 1] as usize);
                    let first = if level == own { first.max(i + 1) } else { first };
                    for j in first..end {
                        if sorted_level[j] == level && sorted_cell[j] == cell {
                            w.pair(i, j);
                        }
                    }
                }
            }
        }
        // Added to the swept tests' counts, if any.
        self.tested += w.tested;
        self.contacts += w.contacts;
        true
    }
}
