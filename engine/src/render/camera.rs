//! Cameras: 2D orthographic views (of a height, or of a field fitted to
//! the frame's shape) and a 3D perspective orbit, all giving a
//! view-projection matrix with wgpu's depth range 0..1.

use glam::{Mat4, Vec2, Vec3};

use crate::math;
use crate::scene::format::{CameraHint, Projection};

/// Where the renderer looks from. Both kinds are plain values: a window
/// changes them with the mouse, a render test fixes them.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Camera {
    /// Orthographic, looking down -z at the x-y plane.
    TwoD {
        /// World point at the centre of the image.
        center: Vec2,
        /// Visible height in world units; the width follows the aspect ratio.
        height: f32,
    },
    /// Orthographic, looking down -z at a field of `size` metres around
    /// `center`, fitted to frames of any shape as `fit` says (a game
    /// designed at 16:9 shown in a 4:3 window).
    Field {
        /// World point at the centre of the field.
        center: Vec2,
        /// The field's width and height in world units.
        size: Vec2,
        /// How the field fills a frame of another shape.
        fit: Fit,
    },
    /// Perspective, orbiting `target` at `distance`.
    Orbit {
        /// The point looked at.
        target: Vec3,
        /// Distance from the target.
        distance: f32,
        /// Rotation about the world y axis, degrees (0: looking down -z).
        yaw: f32,
        /// Elevation above the x-z plane, degrees, within (-89, 89).
        pitch: f32,
        /// Vertical field of view, degrees (default 45).
        fov_y: f32,
    },
}

/// How a [`Camera::Field`] fills a frame whose shape is not the field's,
/// as Bevy's `ScalingMode` does.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Fit {
    /// The field's height exactly; the width follows the frame (more or
    /// less of the world at the sides): [`Camera::TwoD`]'s rule.
    Height,
    /// The field's width exactly; the height follows the frame.
    Width,
    /// The whole field is seen, and more of the world on the two sides
    /// where the frame is relatively longer.
    Contain,
    /// The whole field and nothing else: bars of the background colour
    /// fill the rest of the frame (letterbox above and below, pillarbox at
    /// the sides), and nothing is drawn in them.
    #[default]
    Letterbox,
    /// The field fills the whole frame: its excess on two sides is cut off.
    Cover,
}

/// The part of a frame a camera draws into, in pixels from the top left:
/// the whole frame, but for [`Fit::Letterbox`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FrameRect {
    /// Left edge.
    pub x: f32,
    /// Top edge.
    pub y: f32,
    /// Width.
    pub width: f32,
    /// Height.
    pub height: f32,
}

impl FrameRect {
    /// The whole of a `width` x `height` frame.
    #[must_use]
    pub fn whole(width: u32, height: u32) -> Self {
        Self {
            x: 0.0,
            y: 0.0,
            width: width.max(1) as f32,
            height: height.max(1) as f32,
        }
    }
}

impl Default for Camera {
    /// A 2D view of 10 m around the origin.
    fn default() -> Self {
        Self::TwoD {
            center: Vec2::ZERO,
            height: 10.0,
        }
    }
}

/// A camera's matrices for one image size.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CameraMatrices {
    /// World to clip space.
    pub view_proj: Mat4,
    /// Pixels per world unit at clip w = 1: a sphere of radius `r` at clip
    /// depth `w` covers `r * pixels_per_unit / w` pixels.
    pub pixels_per_unit: f32,
}

impl Camera {
    /// The camera a scene file's hint describes.
    #[must_use]
    pub fn from_hint(hint: &CameraHint) -> Self {
        let target = Vec3::from(hint.target.0);
        match hint.projection {
            Projection::TwoD => Self::TwoD {
                center: target.truncate(),
                height: hint.extent.0,
            },
            Projection::ThreeD => Self::Orbit {
                target,
                distance: hint.extent.0,
                yaw: hint.angles.0.0,
                pitch: hint.angles.1.0,
                fov_y: 45.0,
            },
        }
    }

    /// Whether the camera is orthographic, looking at the x-y plane.
    #[must_use]
    pub fn is_2d(&self) -> bool {
        !matches!(self, Self::Orbit { .. })
    }

    /// The part of a `width` x `height` frame this camera draws into: the
    /// whole frame, but for a letterboxed [`Camera::Field`], the centred
    /// rectangle of the field's shape.
    #[must_use]
    pub fn frame_rect(&self, width: u32, height: u32) -> FrameRect {
        let whole = FrameRect::whole(width, height);
        let Self::Field {
            size,
            fit: Fit::Letterbox,
            ..
        } = *self
        else {
            return whole;
        };
        let field = size.x / size.y;
        if !(field.is_finite() && field > 0.0) {
            return whole;
        }
        let (w, h) = if whole.width / whole.height > field {
            (whole.height * field, whole.height)
        } else {
            (whole.width, whole.width / field)
        };
        FrameRect {
            x: ((whole.width - w) * 0.5).floor(),
            y: ((whole.height - h) * 0.5).floor(),
            width: w.round().max(1.0),
            height: h.round().max(1.0),
        }
    }

    /// Half the width and height of the world a 2D camera shows in a frame
    /// rectangle of `aspect` (width / height); `None` for an orbit camera.
    #[must_use]
    pub fn half_extents(&self, aspect: f32) -> Option<Vec2> {
        match *self {
            Self::TwoD { height, .. } => Some(Vec2::new(0.5 * height * aspect, 0.5 * height)),
            Self::Field { size, fit, .. } => {
                let half = 0.5 * size;
                let by_height = Vec2::new(half.y * aspect, half.y);
                let by_width = Vec2::new(half.x, half.x / aspect);
                let wider = aspect > size.x / size.y;
                Some(match fit {
                    Fit::Height => by_height,
                    Fit::Width => by_width,
                    Fit::Contain if wider => by_height,
                    Fit::Contain => by_width,
                    Fit::Cover if wider => by_width,
                    Fit::Cover => by_height,
                    // The frame rectangle has the field's shape, to a
                    // pixel: fitted whole, a rounding's sliver of world
                    // shows rather than a stretch.
                    Fit::Letterbox if wider => by_height,
                    Fit::Letterbox => by_width,
                })
            }
            Self::Orbit { .. } => None,
        }
    }

    /// The world rectangle `(min, max)` a 2D camera shows in a `width` x
    /// `height` frame (in its [`frame_rect`](Self::frame_rect)); `None` for
    /// an orbit camera.
    #[must_use]
    pub fn visible(&self, width: u32, height: u32) -> Option<(Vec2, Vec2)> {
        let rect = self.frame_rect(width, height);
        let half = self.half_extents(rect.width / rect.height)?;
        let (Self::TwoD { center, .. } | Self::Field { center, .. }) = *self else {
            return None;
        };
        Some((center - half, center + half))
    }

    /// Matrices for an image of `width` x `height` pixels (mapping to the
    /// camera's [`frame_rect`](Self::frame_rect), where it draws).
    #[must_use]
    pub fn matrices(&self, width: u32, height: u32) -> CameraMatrices {
        let rect = self.frame_rect(width, height);
        let aspect = rect.width / rect.height;
        let half_height_px = 0.5 * rect.height;
        match *self {
            Self::TwoD { center, .. } | Self::Field { center, .. } => {
                let half = self.half_extents(aspect).unwrap_or(Vec2::ONE);
                let (w, h) = (half.x, half.y);
                // z in [-1000, 1000] maps into 0..1, so 2D scenes with depth
                // still draw nearest-first by z.
                let proj = glam::camera::rh::proj::directx::orthographic(
                    center.x - w,
                    center.x + w,
                    center.y - h,
                    center.y + h,
                    -1000.0,
                    1000.0,
                );
                CameraMatrices {
                    view_proj: proj,
                    pixels_per_unit: half_height_px / h,
                }
            }
            Self::Orbit {
                target,
                distance,
                yaw,
                pitch,
                fov_y,
            } => {
                let (yaw, pitch) = (yaw.to_radians(), pitch.clamp(-89.0, 89.0).to_radians());
                let eye = target
                    + distance
                        * Vec3::new(
                            math::sin(yaw) * math::cos(pitch),
                            math::sin(pitch),
                            math::cos(yaw) * math::cos(pitch),
                        );
                let view = glam::camera::rh::view::look_at_mat4(eye, target, Vec3::Y);
                let fov = fov_y.clamp(1.0, 170.0).to_radians();
                let near = (distance * 1e-3).max(1e-3);
                let proj = glam::camera::rh::proj::directx::perspective(fov, aspect, near, distance * 100.0 + 100.0);
                CameraMatrices {
                    view_proj: proj * view,
                    pixels_per_unit: half_height_px / math::tan(0.5 * fov),
                }
            }
        }
    }

    /// Turns an orbit camera by mouse-drag angles (degrees); pans a 2D one
    /// by the same amounts scaled to its height.
    pub fn orbit(&mut self, d_yaw: f32, d_pitch: f32) {
        match self {
            Self::TwoD { center, height } => *center += Vec2::new(-d_yaw, d_pitch) * (*height / 360.0),
            Self::Field { center, size, .. } => *center += Vec2::new(-d_yaw, d_pitch) * (size.y / 360.0),
            Self::Orbit { yaw, pitch, .. } => {
                *yaw += d_yaw;
                *pitch = (*pitch + d_pitch).clamp(-89.0, 89.0);
            }
        }
    }

    /// The world point on the `z = 0` plane seen at pixel `(x, y)` (from the
    /// top left) of a `width` x `height` image: the mouse pointer as a game
    /// reads it. `None` where the view does not meet that plane (looking
    /// along it, or the plane behind the camera or past its far plane).
    ///
    /// The pixel's ray runs from its point on the near plane (clip depth 0)
    /// to the far plane (depth 1), both unprojected; it meets z = 0 at
    /// `s = -near.z / (far.z - near.z)`, which must lie in `[0, 1]`.
    #[must_use]
    pub fn point_on_plane(&self, x: f32, y: f32, width: u32, height: u32) -> Option<Vec2> {
        let rect = self.frame_rect(width, height);
        let ndc = Vec2::new(
            2.0 * (x - rect.x) / rect.width - 1.0,
            1.0 - 2.0 * (y - rect.y) / rect.height,
        );
        let inverse = self.matrices(width, height).view_proj.inverse();
        let near = inverse.project_point3(ndc.extend(0.0));
        let far = inverse.project_point3(ndc.extend(1.0));
        let s = -near.z / (far.z - near.z);
        let point = (near + s * (far - near)).truncate();
        ((0.0..=1.0).contains(&s) && point.is_finite()).then_some(point)
    }

    /// The pixel (from the top left of a `width` x `height` frame) at which
    /// the world point `at` is drawn: where a game places a screen-space
    /// marker over a world object. `None` behind an orbit camera.
    #[must_use]
    pub fn pixel_of(&self, at: Vec3, width: u32, height: u32) -> Option<Vec2> {
        let rect = self.frame_rect(width, height);
        let clip = self.matrices(width, height).view_proj * at.extend(1.0);
        if clip.w <= 0.0 {
            return None;
        }
        let ndc = clip.truncate() / clip.w;
        Some(Vec2::new(
            rect.x + (ndc.x + 1.0) * 0.5 * rect.width,
            rect.y + (1.0 - ndc.y) * 0.5 * rect.height,
        ))
    }

    /// Zooms by `factor` (> 1 moves closer / shows less).
    pub fn zoom(&mut self, factor: f32) {
        if !(factor.is_finite() && factor > 0.0) {
            return;
        }
        match self {
            Self::TwoD { height, .. } => *height /= factor,
            Self::Field { size, .. } => *size /= factor,
            Self::Orbit { distance, .. } => *distance /= factor,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn two_d_maps_the_visible_rectangle_to_clip_space() {
        let camera = Camera::TwoD {
            center: Vec2::new(1.0, 2.0),
            height: 4.0,
        };
        let m = camera.matrices(200, 100);
        // Height 4 around y = 2; width 8 around x = 1.
        let corner = m.view_proj.project_point3(Vec3::new(5.0, 4.0, 0.0));
        assert!(
            (corner.x - 1.0).abs() < 1e-6 && (corner.y - 1.0).abs() < 1e-6,
            "{corner}"
        );
        let centre = m.view_proj.project_point3(Vec3::new(1.0, 2.0, 0.0));
        assert!(centre.x.abs() < 1e-6 && centre.y.abs() < 1e-6);
        assert!((0.0..=1.0).contains(&centre.z));
        assert!((m.pixels_per_unit - 25.0).abs() < 1e-5); // 100 px for 4 m
    }

    #[test]
    fn the_pointer_finds_the_world_point_under_it() {
        let camera = Camera::TwoD {
            center: Vec2::new(0.0, 5.0),
            height: 10.0,
        };
        // 200 x 100 px: 10 px per metre, 20 m wide.
        let at = |x, y| camera.point_on_plane(x, y, 200, 100).expect("on the plane");
        assert!(at(100.0, 50.0).abs_diff_eq(Vec2::new(0.0, 5.0), 1e-4));
        assert!(at(0.0, 0.0).abs_diff_eq(Vec2::new(-10.0, 10.0), 1e-4));
        assert!(at(150.0, 100.0).abs_diff_eq(Vec2::new(5.0, 0.0), 1e-4));
        // Looking down at the plane from above: the centre is the target.
        let above = Camera::Orbit {
            target: Vec3::new(1.0, 2.0, 0.0),
            distance: 10.0,
            yaw: 0.0,
            pitch: 0.0,
            fov_y: 45.0,
        };
        let centre = above.point_on_plane(50.0, 50.0, 100, 100).expect("seen");
        assert!(centre.abs_diff_eq(Vec2::new(1.0, 2.0), 1e-3), "{centre}");
        // From the side (yaw 90) at z = 5, looking parallel to the plane:
        // the centre ray never meets it.
        let along = Camera::Orbit {
            yaw: 90.0,
            pitch: 0.0,
            target: Vec3::new(0.0, 0.0, 5.0),
            distance: 10.0,
            fov_y: 45.0,
        };
        assert_eq!(along.point_on_plane(50.0, 50.0, 100, 100), None);
    }

    /// A 16 x 9 m field in a 4:3 frame (400 x 300 px) and a 21:9 one
    /// (420 x 180 px), each way of fitting it.
    #[test]
    fn a_field_fits_frames_of_other_shapes_as_asked() {
        let field = |fit| Camera::Field {
            center: Vec2::new(1.0, 2.0),
            size: Vec2::new(16.0, 9.0),
            fit,
        };
        let shown = |fit, w, h| {
            let (min, max) = field(fit).visible(w, h).expect("2D");
            max - min
        };
        let close = |a: Vec2, b: Vec2| a.abs_diff_eq(b, 1e-3);
        // 4:3, narrower than the field.
        assert!(
            close(shown(Fit::Height, 400, 300), Vec2::new(12.0, 9.0)),
            "the sides cut"
        );
        assert!(close(shown(Fit::Width, 400, 300), Vec2::new(16.0, 12.0)));
        assert!(
            close(shown(Fit::Contain, 400, 300), Vec2::new(16.0, 12.0)),
            "more above and below"
        );
        assert!(
            close(shown(Fit::Cover, 400, 300), Vec2::new(12.0, 9.0)),
            "the sides cut"
        );
        assert!(
            close(shown(Fit::Letterbox, 400, 300), Vec2::new(16.0, 9.0)),
            "exactly the field"
        );
        // 21:9, wider than the field.
        assert!(close(shown(Fit::Height, 420, 180), Vec2::new(21.0, 9.0)));
        assert!(
            close(shown(Fit::Contain, 420, 180), Vec2::new(21.0, 9.0)),
            "more at the sides"
        );
        assert!(close(
            shown(Fit::Cover, 420, 180),
            Vec2::new(16.0, 16.0 * 180.0 / 420.0)
        ));
        assert!(close(shown(Fit::Letterbox, 420, 180), Vec2::new(16.0, 9.0)));
        // Letterbox: bars above and below at 4:3 (400 x 225 in the middle),
        // at the sides at 21:9 (320 x 180).
        let bars = field(Fit::Letterbox).frame_rect(400, 300);
        assert_eq!((bars.x, bars.y, bars.width, bars.height), (0.0, 37.0, 400.0, 225.0));
        let pillars = field(Fit::Letterbox).frame_rect(420, 180);
        assert_eq!(
            (pillars.x, pillars.y, pillars.width, pillars.height),
            (50.0, 0.0, 320.0, 180.0)
        );
        assert_eq!(field(Fit::Contain).frame_rect(400, 300), FrameRect::whole(400, 300));
        // The pointer and the drawing agree, bars included: the field's
        // top-left corner is the rectangle's.
        let camera = field(Fit::Letterbox);
        let corner = camera.pixel_of(Vec3::new(-7.0, 6.5, 0.0), 400, 300).expect("2D");
        assert!(corner.abs_diff_eq(Vec2::new(0.0, 37.0), 1e-3), "{corner}");
        let back = camera
            .point_on_plane(corner.x, corner.y, 400, 300)
            .expect("on the plane");
        assert!(back.abs_diff_eq(Vec2::new(-7.0, 6.5), 1e-3), "{back}");
        let middle = camera
            .point_on_plane(200.0, 37.0 + 112.5, 400, 300)
            .expect("on the plane");
        assert!(middle.abs_diff_eq(Vec2::new(1.0, 2.0), 1e-3), "{middle}");
        // 25 px a metre in the 225 px rectangle.
        assert!((camera.matrices(400, 300).pixels_per_unit - 25.0).abs() < 1e-4);
    }

    #[test]
    fn orbit_puts_the_target_at_the_centre_and_sizes_by_distance() {
        let camera = Camera::Orbit {
            target: Vec3::new(0.0, 1.0, 0.0),
            distance: 10.0,
            yaw: 30.0,
            pitch: 20.0,
            fov_y: 90.0,
        };
        let m = camera.matrices(100, 100);
        let clip = m.view_proj * Vec3::new(0.0, 1.0, 0.0).extend(1.0);
        assert!((clip.x / clip.w).abs() < 1e-5 && (clip.y / clip.w).abs() < 1e-5);
        assert!((clip.w - 10.0).abs() < 1e-4, "w is the view depth: {}", clip.w);
        // fov 90: half height 50 px at tan 45 = 1 -> 50 px per unit at w = 1.
        assert!((m.pixels_per_unit - 50.0).abs() < 1e-3);
    }
}
