//! Filled cells as few rectangles: the greedy rule of "greedy meshing".
//!
//! From the top-left cell, row by row: an uncovered filled cell starts a
//! rectangle, which grows right while the cells are filled and uncovered,
//! then down while the row below has the same run (no wider: a floor
//! under a pillar keeps its whole width for its own box). Every filled
//! cell ends in exactly one rectangle, and the same cells give the same
//! rectangles in the same order. A solid floor of a platformer becomes one
//! box, where a box a tile would give a body a seam at every tile.

/// The rectangles `[x, y, width, height]` (cells; `y` counts rows down from
/// the top) covering the cells of a `width` x `height` grid that `filled`
/// (row by row from the top) marks, each cell once.
#[must_use]
pub fn merge_cells(filled: &[bool], width: u32, height: u32) -> Vec<[u32; 4]> {
    let (w, h) = (width as usize, height as usize);
    let at = |x: usize, y: usize| filled.get(y * w + x).copied().unwrap_or(false);
    let mut covered = vec![false; w * h];
    let mut out = Vec::new();
    for y in 0..h {
        let mut x = 0;
        while x < w {
            if !at(x, y) || covered[y * w + x] {
                x += 1;
                continue;
            }
            let mut run = 1;
            while x + run < w && at(x + run, y) && !covered[y * w + x + run] {
                run += 1;
            }
            // Down while the row below's run here is the same one: a wider
            // run below (a floor under a pillar) stays whole for its own box.
            let free = |c: usize, row: usize| at(c, row) && !covered[row * w + c];
            let mut rows = 1;
            while y + rows < h
                && (x..x + run).all(|c| free(c, y + rows))
                && (x == 0 || !free(x - 1, y + rows))
                && (x + run == w || !free(x + run, y + rows))
            {
                rows += 1;
            }
            for row in y..y + rows {
                covered[row * w + x..row * w + x + run].fill(true);
            }
            out.push([x as u32, y as u32, run as u32, rows as u32]);
            x += run;
        }
    }
    out
}
