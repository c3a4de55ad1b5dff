//! A sprite: a texture (or a region of it, for an atlas) drawn as a
//! rectangle in the world, placed by a pivot, turned, scaled and tinted.
//!
//! ```text
//! corner c of the unit square (0..1, y up), uv from the region:
//!   world = at + rotate(rotation) ((c - pivot) size)
//! colour = texel * tint        (both straight alpha, tint sRGB)
//! ```

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
        let (u0, v0) = (x as f32 / w as f32, y as f32 / h as f32);
        let (u1, v1) = ((x + rw) as f32 / w as f32, (y + rh) as f32 / h as f32);
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
