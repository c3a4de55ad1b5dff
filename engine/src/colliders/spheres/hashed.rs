//! The hashed grid, for spheres of one size spread far apart (a dense grid
//! would hold more than [`DENSE_CELLS`](super::DENSE_CELLS) cells a
//! particle): cells are hashed into `2^k >= 2 n` buckets and the 27
//! neighbouring buckets are checked cell by cell.

use super::SphereCollisions;
use super::cells::{NEIGHBOURS, hash, neighbour};
use super::columns::map_into;
use super::narrow::Window;
use crate::colliders::ContactColumns;

impl SphereCollisions {
    pub(super) fn resolve_hashed(&mut self, c: &ContactColumns<'_>) -> bool {
        let n = c.position.len();
        let buckets = (2 * n).next_power_of_two();
        let mask = (buckets - 1) as u32;
        map_into(&mut self.key, &self.cell, c.parallel, |cell| hash(*cell, 0, mask));
        if !self.sort_and_gather(buckets, c) {
            return false;
        }
        let (sorted_cell, starts) = (&self.sorted_cell, &self.starts);
        let mut w = Window::whole(
            [&mut self.x, &mut self.y, &mut self.z],
            &mut self.velocity,
            &self.radius,
            &self.inverse_mass,
            self.material,
            self.recording.then_some(&mut self.pairs),
        );
        for i in 0..n {
            let home = sorted_cell[i];
            for offset in NEIGHBOURS {
                let Some(cell) = neighbour(home, offset) else {
                    continue;
                };
                let b = hash(cell, 0, mask) as usize;
                let (first, end) = (starts[b] as usize, starts[b + 1] as usize);
                for j in first.max(i + 1)..end {
                    // Other cells share the bucket (hash collisions); and a
                    // bucket shared by two neighbouring cells is visited
                    // twice, but each partner belongs to one cell only.
                    if sorted_cell[j] == cell {
                        w.pair(i, j);
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
