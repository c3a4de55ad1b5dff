//! A sprite: a texture (or a region of it, for an atlas) drawn as a
//! rectangle in the world, placed by a pivot, turned, scaled and tinted.
//!
//! ```text
//! corner c of the unit square (0..1, y up), uv from the region
//! (mirrored on x and y by flip_x and flip_y):
//!   world = at + rotate(rotation) ((c - pivot) size)
//! colour = texel * tint        (both straight alpha, tint sRGB)
//! ```
//!
//! An atlas animation ([`Animation`]) picks the region from a count of
//! fixed steps, so a replay or a rollback draws the same frame.

use glam::Vec2;

use super::texture::Texture;

/// One sprite of a frame ([`Draw::sprite`](crate::app::Draw::sprite)).
#[derive(Clone, Debug, PartialEq)]
pub struct Sprite {
    /// The image.
    pub texture: Texture,
    /// Where the pivot goes, world space (metres; the z = 0 plane).
    pub at: Vec2,
    /// Width and height in world units (metres).
    pub size: Vec2,
    /// Turn about the pivot, radians counter-clockwise (default 0).
    pub rotation: f32,
    /// The point of the rectangle at `at`, as fractions of its size from
    /// its bottom-left corner (default `(0.5, 0.5)`: the centre).
    pub pivot: Vec2,
    /// Multiplies the texture's colour, sRGB RGBA (default white: as is).
    pub tint: [u8; 4],
    /// The texture's region drawn, in pixels from its top left: `[x, y,
    /// width, height]` (default the whole texture): one frame of an atlas.
    pub region: Option<[u32; 4]>,
    /// Linear filtering when scaled (default false: nearest texels, crisp
    /// pixel art).
    pub smooth: bool,
    /// Mirrored left to right (default false): a character facing the
    /// other way, without a second image.
    pub flip_x: bool,
    /// Mirrored top to bottom (default false).
    pub flip_y: bool,
}

impl Sprite {
    /// `texture` drawn `size` metres large, centred at `at`.
    #[must_use]
    pub fn new(texture: &Texture, at: Vec2, size: Vec2) -> Self {
        Self {
            texture: texture.clone(),
            at,
            size,
            rotation: 0.0,
            pivot: Vec2::splat(0.5),
            tint: [255; 4],
            region: None,
            smooth: false,
            flip_x: false,
            flip_y: false,
        }
    }

    /// Turns it by `radians` about its pivot.
    pub fn rotation(&mut self, radians: f32) -> &mut Self {
        self.rotation = radians;
        self
    }

    /// Places it by `pivot` (fractions of its size from the bottom left).
    pub fn pivot(&mut self, pivot: Vec2) -> &mut Self {
        self.pivot = pivot;
        self
    }

    /// Multiplies its colour by `tint` (sRGB RGBA).
    pub fn tint(&mut self, tint: [u8; 4]) -> &mut Self {
        self.tint = tint;
        self
    }

    /// Draws only the region `[x, y, width, height]` (pixels from the
    /// texture's top left) of its texture.
    pub fn region(&mut self, region: [u32; 4]) -> &mut Self {
        self.region = Some(region);
        self
    }

    /// Filters it linearly when scaled (a photo), rather than by nearest
    /// texel (pixel art).
    pub fn smooth(&mut self) -> &mut Self {
        self.smooth = true;
        self
    }

    /// Mirrors it left to right if `flip` (a walker facing left:
    /// `.flip_x(velocity.x < 0.0)`); the pivot stays where it is.
    pub fn flip_x(&mut self, flip: bool) -> &mut Self {
        self.flip_x = flip;
        self
    }

    /// Mirrors it top to bottom if `flip`.
    pub fn flip_y(&mut self, flip: bool) -> &mut Self {
        self.flip_y = flip;
        self
    }

    /// Draws the frame of `animation` shown `ticks` fixed steps after it
    /// started (its region).
    pub fn animate(&mut self, animation: &Animation, ticks: u64) -> &mut Self {
        self.region = Some(animation.frame_at(ticks));
        self
    }

    /// Its four corners in the world (bottom-left, bottom-right, top-right,
    /// top-left) and their texture coordinates; or what is wrong with it.
    pub(crate) fn corners(&self) -> Result<[(Vec2, Vec2); 4], String> {
        for (field, ok) in [
            ("at", self.at.is_finite()),
            ("size", self.size.is_finite()),
            ("rotation", self.rotation.is_finite()),
            ("pivot", self.pivot.is_finite()),
        ] {
            if !ok {
                return Err(format!("its {field} is not finite"));
            }
        }
        let (w, h) = (self.texture.width(), self.texture.height());
        let [x, y, rw, rh] = self.region.unwrap_or([0, 0, w, h]);
        let inside =
            rw > 0 && rh > 0 && x.checked_add(rw).is_some_and(|r| r <= w) && y.checked_add(rh).is_some_and(|b| b <= h);
        if !inside {
            return Err(format!(
                "its region [{x}, {y}, {rw}, {rh}] is not a non-empty part of its {w} x {h} texture"
            ));
        }
        let (mut u0, mut v0) = (x as f32 / w as f32, y as f32 / h as f32);
        let (mut u1, mut v1) = ((x + rw) as f32 / w as f32, (y + rh) as f32 / h as f32);
        if self.flip_x {
            core::mem::swap(&mut u0, &mut u1);
        }
        if self.flip_y {
            core::mem::swap(&mut v0, &mut v1);
        }
        let turn = Vec2::new(crate::math::cos(self.rotation), crate::math::sin(self.rotation));
        let place = |c: Vec2| self.at + turn.rotate((c - self.pivot) * self.size);
        Ok([
            (place(Vec2::new(0.0, 0.0)), Vec2::new(u0, v1)),
            (place(Vec2::new(1.0, 0.0)), Vec2::new(u1, v1)),
            (place(Vec2::new(1.0, 1.0)), Vec2::new(u1, v0)),
            (place(Vec2::new(0.0, 1.0)), Vec2::new(u0, v0)),
        ])
    }
}

/// An atlas animation: frames (regions of one texture, `[x, y, width,
/// height]` in pixels from its top left) shown for `ticks_per_frame` fixed
/// steps each, looping or once. It is a pure function of the steps since
/// it started (a game keeps that count in its state, where the checksum,
/// a replay and a rollback see it), so every run draws the same frame.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Animation {
    /// The frames, in order (at least one).
    pub frames: Vec<[u32; 4]>,
    /// Fixed steps each frame is shown (at least 1).
    pub ticks_per_frame: u32,
    /// Whether it starts again after its last frame (default true), or
    /// stays on it (once: an explosion, a death).
    pub looping: bool,
}

impl Animation {
    /// `count` frames of `size` pixels laid out left to right from `origin`
    /// (pixels from the texture's top left) in a row of an atlas, each shown
    /// `ticks_per_frame` fixed steps, looping: a walk cycle.
    ///
    /// # Errors
    /// What is wrong, naming the field: no frames, no steps a frame, an
    /// empty frame, or a row past `u32`'s pixels.
    pub fn row(origin: [u32; 2], size: [u32; 2], count: u32, ticks_per_frame: u32) -> Result<Self, String> {
        let [x0, y] = origin;
        let [w, h] = size;
        if count == 0 || w == 0 || h == 0 {
            return Err(format!(
                "an animation needs frames of some size: count {count}, size {w} x {h} (each at least 1)"
            ));
        }
        let frames = (0..count)
            .map(|k| k.checked_mul(w).and_then(|dx| x0.checked_add(dx)).map(|x| [x, y, w, h]))
            .collect::<Option<Vec<_>>>()
            .ok_or_else(|| format!("{count} frames {w} px wide from x = {x0} go past {} pixels", u32::MAX))?;
        let animation = Self {
            frames,
            ticks_per_frame,
            looping: true,
        };
        animation.check()?;
        Ok(animation)
    }

    /// Plays once, staying on its last frame.
    #[must_use]
    pub fn once(mut self) -> Self {
        self.looping = false;
        self
    }

    /// What is wrong with it, naming the field, if anything.
    ///
    /// # Errors
    /// No frames, or `ticks_per_frame` 0.
    pub fn check(&self) -> Result<(), String> {
        if self.frames.is_empty() {
            return Err("an animation's frames: none (at least one)".into());
        }
        if self.ticks_per_frame == 0 {
            return Err("an animation's ticks_per_frame: 0 (at least 1)".into());
        }
        Ok(())
    }

    /// The frame shown `ticks` fixed steps after it started: frame
    /// `ticks / ticks_per_frame`, modulo the frames when looping, else the
    /// last once past it. (An animation [`check`](Self::check) refuses
    /// shows its first frame, or the whole texture's region `[0, 0, 0, 0]`
    /// without frames, which draws as the error naming the region.)
    #[must_use]
    pub fn frame_at(&self, ticks: u64) -> [u32; 4] {
        let count = self.frames.len() as u64;
        if count == 0 {
            return [0; 4];
        }
        let k = ticks / u64::from(self.ticks_per_frame.max(1));
        let k = if self.looping { k % count } else { k.min(count - 1) };
        self.frames[k as usize]
    }

    /// Whether a one-shot animation has shown its last frame for its full
    /// time `ticks` fixed steps after it started (never when looping).
    #[must_use]
    pub fn finished(&self, ticks: u64) -> bool {
        !self.looping && ticks / u64::from(self.ticks_per_frame.max(1)) >= self.frames.len() as u64
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn texture() -> Texture {
        // 4 x 2: the left half red, the right half blue.
        let mut pixels = Vec::new();
        for _ in 0..2 {
            for x in 0..4 {
                pixels.extend_from_slice(if x < 2 { &[255, 0, 0, 255] } else { &[0, 0, 255, 255] });
            }
        }
        Texture::from_rgba(4, 2, pixels).expect("a texture")
    }

    #[test]
    fn flipping_mirrors_the_texture_coordinates_and_keeps_the_corners() {
        let plain = Sprite::new(&texture(), Vec2::new(1.0, 2.0), Vec2::new(2.0, 1.0));
        let mut flipped = plain.clone();
        flipped.flip_x(true);
        let (a, b) = (plain.corners().expect("valid"), flipped.corners().expect("valid"));
        for k in 0..4 {
            assert_eq!(a[k].0, b[k].0, "corner {k} stays");
            assert_eq!(b[k].1.x, 1.0 - a[k].1.x, "corner {k}'s u mirrored");
            assert_eq!(b[k].1.y, a[k].1.y, "corner {k}'s v kept");
        }
        flipped.flip_x(false).flip_y(true);
        let c = flipped.corners().expect("valid");
        for k in 0..4 {
            assert_eq!(
                (c[k].1.x, c[k].1.y),
                (a[k].1.x, 1.0 - a[k].1.y),
                "corner {k}: v mirrored"
            );
        }
        // A region flips within itself: [2, 0, 2, 2] is u 0.5..1.
        let mut region = plain.clone();
        region.region([2, 0, 2, 2]).flip_x(true);
        let r = region.corners().expect("valid");
        assert_eq!(
            (r[0].1.x, r[1].1.x),
            (1.0, 0.5),
            "bottom-left shows the region's right edge"
        );
    }

    #[test]
    fn an_animation_shows_its_frames_by_ticks_looping_or_once() {
        let walk = Animation::row([0, 16], [8, 8], 4, 3).expect("a walk");
        assert_eq!(walk.frames.len(), 4);
        let xs: Vec<u32> = (0..15).map(|t| walk.frame_at(t)[0]).collect();
        assert_eq!(xs, [0, 0, 0, 8, 8, 8, 16, 16, 16, 24, 24, 24, 0, 0, 0]);
        assert!(!walk.finished(1_000));
        let boom = walk.clone().once();
        assert_eq!(boom.frame_at(11)[0], 24);
        assert_eq!(boom.frame_at(u64::MAX)[0], 24, "stays on its last frame");
        assert!(!boom.finished(11) && boom.finished(12));
        let mut sprite = Sprite::new(&texture(), Vec2::ZERO, Vec2::ONE);
        sprite.animate(&walk, 4);
        assert_eq!(sprite.region, Some([8, 16, 8, 8]));
        assert_eq!(
            Animation::row([0, 0], [8, 8], 0, 3).expect_err("no frames"),
            "an animation needs frames of some size: count 0, size 8 x 8 (each at least 1)"
        );
        assert_eq!(
            Animation::row([0, 0], [8, 8], 2, 0).expect_err("no steps"),
            "an animation's ticks_per_frame: 0 (at least 1)"
        );
        assert!(
            Animation::row([u32::MAX - 4, 0], [8, 8], 2, 1)
                .expect_err("past u32")
                .contains("go past 4294967295 pixels")
        );
    }
}
