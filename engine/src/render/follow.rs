//! A 2D camera that follows a target: a dead zone the target moves in
//! freely, smoothing that closes part of the rest each update, and bounds
//! the view stays inside (a level's edges).
//!
//! ```text
//! d      = target - center
//! beyond = d - clamp(d, -dead_zone, dead_zone)      (0 inside the dead zone)
//! center = center + smoothing beyond                 (smoothing in (0, 1])
//! center = clamp(center, min + half, max - half)     per axis, with bounds;
//!          the bounds' middle on an axis they are narrower than the view
//! ```
//!
//! Plain `f32` arithmetic, the same bits on every platform, and no window
//! read: called once a fixed step it replays exactly. For rollback keep the
//! centre in the game's own state ([`Follow::next_center`]) and set the
//! camera from it in `draw`.

use glam::Vec2;

use super::camera::Camera;

/// How a camera follows its target ([`Camera::follow`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Follow {
    /// Half the size of the box around the view's centre the target moves
    /// in without moving the camera, metres (default zero: always centred).
    pub dead_zone: Vec2,
    /// The fraction of the way past the dead zone the centre moves each
    /// update, in (0, 1] (default 1: at once; 0.1 at 60 Hz eases in about
    /// half a second).
    pub smoothing: f32,
    /// The world rectangle `(min, max)` the view stays inside (default
    /// `None`: anywhere).
    pub bounds: Option<(Vec2, Vec2)>,
}

impl Default for Follow {
    fn default() -> Self {
        Self {
            dead_zone: Vec2::ZERO,
            smoothing: 1.0,
            bounds: None,
        }
    }
}

impl Follow {
    /// What is wrong with these settings, naming the field and the
    /// accepted range, if anything.
    ///
    /// # Errors
    /// A dead zone not finite or negative, smoothing outside (0, 1], or
    /// bounds not finite or with `min` past `max`.
    pub fn check(&self) -> Result<(), String> {
        if !(self.dead_zone.is_finite() && self.dead_zone.cmpge(Vec2::ZERO).all()) {
            return Err(format!(
                "Follow::dead_zone {} is not finite and at least zero on both axes",
                self.dead_zone
            ));
        }
        if !(self.smoothing > 0.0 && self.smoothing <= 1.0) {
            return Err(format!("Follow::smoothing {} is not in (0, 1]", self.smoothing));
        }
        if let Some((min, max)) = self.bounds
            && !(min.is_finite() && max.is_finite() && min.cmple(max).all())
        {
            return Err(format!(
                "Follow::bounds ({min}, {max}) are not finite with min at most max on both axes"
            ));
        }
        Ok(())
    }

    /// The view's centre after one update from `center` toward `target`,
    /// for a view of half extents `half` (the bounds are kept only when it
    /// is given). Settings that [`check`](Self::check) refuses give
    /// `center` unchanged.
    #[must_use]
    pub fn next_center(&self, center: Vec2, target: Vec2, half: Option<Vec2>) -> Vec2 {
        if self.check().is_err() || !target.is_finite() {
            return center;
        }
        let d = target - center;
        let beyond = d - d.clamp(-self.dead_zone, self.dead_zone);
        let mut next = center + beyond * self.smoothing;
        if let (Some((min, max)), Some(half)) = (self.bounds, half) {
            for axis in 0..2 {
                let (low, high) = (min[axis] + half[axis], max[axis] - half[axis]);
                next[axis] = if low <= high {
                    next[axis].clamp(low, high)
                } else {
                    0.5 * (min[axis] + max[axis])
                };
            }
        }
        next
    }
}

impl Camera {
    /// Moves a 2D camera's centre one update toward `target` as `follow`
    /// says. The bounds keep what the camera is designed to show inside
    /// them, whatever the window: a [`Camera::Field`]'s field (all a
    /// letterboxed window shows), a [`Camera::TwoD`]'s height (and its
    /// centre, across). That depends on no window, so it may be called once
    /// a fixed step in `fixed_update` and replays exactly.
    ///
    /// # Errors
    /// An orbit camera (it has no centre in the plane), a target that is
    /// not finite, or settings [`Follow::check`] refuses.
    pub fn follow(&mut self, follow: &Follow, target: Vec2) -> Result<(), String> {
        follow.check()?;
        if !target.is_finite() {
            return Err(format!("a camera cannot follow a target at {target}: not finite"));
        }
        match self {
            Self::TwoD { center, height } => {
                let half = Vec2::new(0.0, 0.5 * *height);
                *center = follow.next_center(*center, target, Some(half));
                Ok(())
            }
            Self::Field { center, size, .. } => {
                *center = follow.next_center(*center, target, Some(0.5 * *size));
                Ok(())
            }
            Self::Orbit { .. } => {
                Err("an orbit camera does not follow a point in the plane: use Camera::TwoD or Camera::Field".into())
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::render::Fit;

    #[test]
    fn the_centre_waits_in_the_dead_zone_eases_past_it_and_stays_in_bounds() {
        let follow = Follow {
            dead_zone: Vec2::new(1.0, 0.5),
            smoothing: 0.5,
            bounds: None,
        };
        // Inside the dead zone: nothing moves.
        assert_eq!(follow.next_center(Vec2::ZERO, Vec2::new(0.9, -0.5), None), Vec2::ZERO);
        // Past it: half the way past, each axis on its own.
        assert_eq!(
            follow.next_center(Vec2::ZERO, Vec2::new(3.0, -1.5), None),
            Vec2::new(1.0, -0.5)
        );
        // At once, without smoothing.
        let at_once = Follow::default();
        assert_eq!(
            at_once.next_center(Vec2::ZERO, Vec2::new(3.0, 4.0), None),
            Vec2::new(3.0, 4.0)
        );
        // Bounds 0..20 x 0..10 and a view 8 x 4 m: the centre stays in 4..16 x 2..8.
        let bounded = Follow {
            bounds: Some((Vec2::ZERO, Vec2::new(20.0, 10.0))),
            ..Follow::default()
        };
        let half = Some(Vec2::new(4.0, 2.0));
        assert_eq!(
            bounded.next_center(Vec2::new(10.0, 5.0), Vec2::new(-3.0, 30.0), half),
            Vec2::new(4.0, 8.0)
        );
        // A level narrower than the view: its middle on that axis.
        let narrow = Follow {
            bounds: Some((Vec2::ZERO, Vec2::new(6.0, 10.0))),
            ..Follow::default()
        };
        assert_eq!(
            narrow.next_center(Vec2::ZERO, Vec2::new(9.0, 5.0), half),
            Vec2::new(3.0, 5.0)
        );
    }

    #[test]
    fn a_camera_follows_by_its_own_view_and_refuses_what_it_cannot() {
        // A 16 x 9 m field (what a 1600 x 900 frame shows), bounds 0..40 x 0..9.
        let mut camera = Camera::Field {
            center: Vec2::new(8.0, 4.5),
            size: Vec2::new(16.0, 9.0),
            fit: Fit::Letterbox,
        };
        let follow = Follow {
            bounds: Some((Vec2::ZERO, Vec2::new(40.0, 9.0))),
            ..Follow::default()
        };
        camera.follow(&follow, Vec2::new(20.0, 7.0)).expect("follows");
        assert_eq!(
            camera.visible(1600, 900),
            Some((Vec2::new(12.0, 0.0), Vec2::new(28.0, 9.0)))
        );
        camera.follow(&follow, Vec2::new(39.0, 0.0)).expect("follows");
        assert_eq!(
            camera.visible(1600, 900),
            Some((Vec2::new(24.0, 0.0), Vec2::new(40.0, 9.0)))
        );
        assert_eq!(
            camera.follow(
                &Follow {
                    smoothing: 0.0,
                    ..follow
                },
                Vec2::ZERO
            ),
            Err("Follow::smoothing 0 is not in (0, 1]".into())
        );
        assert_eq!(
            camera.follow(&follow, Vec2::new(f32::NAN, 0.0)),
            Err("a camera cannot follow a target at [NaN, 0]: not finite".into())
        );
        // A 2D camera 10 m high keeps its height in bounds 0..40 x 0..9
        // (narrower than it: their middle), its centre across.
        let mut two_d = Camera::TwoD {
            center: Vec2::ZERO,
            height: 10.0,
        };
        two_d.follow(&follow, Vec2::new(45.0, 30.0)).expect("follows");
        assert_eq!(
            two_d,
            Camera::TwoD {
                center: Vec2::new(40.0, 4.5),
                height: 10.0
            }
        );
        let mut orbit = Camera::Orbit {
            target: glam::Vec3::ZERO,
            distance: 10.0,
            yaw: 0.0,
            pitch: 20.0,
            fov_y: 45.0,
        };
        let before = orbit;
        assert_eq!(
            orbit.follow(&follow, Vec2::ZERO),
            Err("an orbit camera does not follow a point in the plane: use Camera::TwoD or Camera::Field".into())
        );
        assert_eq!(orbit, before, "left as it was");
    }
}
