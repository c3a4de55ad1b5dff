//! Cameras: a 2D orthographic view and a 3D perspective orbit, both giving
//! a view-projection matrix with wgpu's depth range 0..1.

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

    /// Matrices for an image of `width` x `height` pixels.
    #[must_use]
    pub fn matrices(&self, width: u32, height: u32) -> CameraMatrices {
        let aspect = width.max(1) as f32 / height.max(1) as f32;
        let half_height_px = 0.5 * height.max(1) as f32;
        match *self {
            Self::TwoD { center, height } => {
                let h = 0.5 * height;
                let w = h * aspect;
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
        let (w, h) = (width.max(1) as f32, height.max(1) as f32);
        let ndc = Vec2::new(2.0 * x / w - 1.0, 1.0 - 2.0 * y / h);
        let inverse = self.matrices(width, height).view_proj.inverse();
        let near = inverse.project_point3(ndc.extend(0.0));
        let far = inverse.project_point3(ndc.extend(1.0));
        let s = -near.z / (far.z - near.z);
        let point = (near + s * (far - near)).truncate();
        ((0.0..=1.0).contains(&s) && point.is_finite()).then_some(point)
    }

    /// Zooms by `factor` (> 1 moves closer / shows less).
    pub fn zoom(&mut self, factor: f32) {
        if !(factor.is_finite() && factor > 0.0) {
            return;
        }
        match self {
            Self::TwoD { height, .. } => *height /= factor,
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
