use glam::Vec2;

use super::merge::merge_cells;
use super::orientation;
use super::read::plain;

/// The grid `rows` draws ('#' filled), row 0 at the top.
fn grid(rows: &[&str]) -> (Vec<bool>, u32, u32) {
    let filled = rows.iter().flat_map(|r| r.bytes().map(|b| b == b'#')).collect();
    (filled, rows[0].len() as u32, rows.len() as u32)
}

#[test]
fn merged_rectangles_cover_every_filled_cell_once_and_a_floor_is_one_box() {
    let rows = [
        "..##....", //
        "..##..#.", //
        "########", //
        "########", //
    ];
    let (filled, w, h) = grid(&rows);
    let boxes = merge_cells(&filled, w, h);
    assert_eq!(boxes, vec![[2, 0, 2, 2], [6, 1, 1, 1], [0, 2, 8, 2]]);
    let mut covered = vec![0u32; filled.len()];
    for [x, y, bw, bh] in boxes {
        for row in y..y + bh {
            for column in x..x + bw {
                covered[(row * w + column) as usize] += 1;
            }
        }
    }
    let expected: Vec<u32> = filled.iter().map(|&f| u32::from(f)).collect();
    assert_eq!(covered, expected, "each filled cell in exactly one box");
}

#[test]
fn merging_a_checkerboard_gives_a_box_a_cell_and_an_empty_grid_none() {
    let (filled, w, h) = grid(&["#.#", ".#.", "#.#"]);
    assert_eq!(merge_cells(&filled, w, h).len(), 5);
    let (empty, w, h) = grid(&["...", "..."]);
    assert!(merge_cells(&empty, w, h).is_empty());
}

/// Where the sprite `(turn, flip_x, flip_y)` sends the image's corner
/// `corner` (y up, about its centre).
fn drawn(turn: f32, fx: bool, fy: bool, corner: Vec2) -> Vec2 {
    let mirrored = Vec2::new(
        if fx { -corner.x } else { corner.x },
        if fy { -corner.y } else { corner.y },
    );
    Vec2::from_angle(turn).rotate(mirrored).round()
}

#[test]
fn tileds_eight_flips_become_a_turn_and_mirrors_that_move_the_corners_as_tiled_does() {
    // The image's top-left corner (y up: (-1, 1)) under Tiled's flips,
    // worked by hand in the image's own axes (x right, y down): the
    // diagonal flip swaps x and y, then h negates x, then v negates y.
    let top_left = Vec2::new(-1.0, 1.0);
    let top_right = Vec2::new(1.0, 1.0);
    for (h, v, d) in (0..8).map(|k| (k & 1 != 0, k & 2 != 0, k & 4 != 0)) {
        let image = |p: Vec2| {
            // To the image's axes, flipped, and back.
            let (mut x, mut y) = (p.x, -p.y);
            if d {
                (x, y) = (y, x);
            }
            if h {
                x = -x;
            }
            if v {
                y = -y;
            }
            Vec2::new(x, -y)
        };
        let (turn, fx, fy) = orientation([h, v, d]);
        for corner in [top_left, top_right] {
            assert_eq!(
                drawn(turn, fx, fy, corner),
                image(corner),
                "flips h {h} v {v} d {d}: corner {corner}"
            );
        }
    }
}

#[test]
fn asset_paths_are_made_plain() {
    assert_eq!(
        plain("maps/./a/../tiles.png".as_ref()),
        std::path::Path::new("maps/tiles.png")
    );
    assert_eq!(plain("../x.png".as_ref()), std::path::Path::new("../x.png"));
}
