//! The plane's lanes against the exact rule, and the chunk's bookkeeping
//! (padding lanes).

use glam::Vec3;

use super::*;
use crate::colliders::{Collider, Material, Plane};
use crate::forces::{Force, Gravity, LinearDrag};
use crate::step::in_step::Sweep;

/// A short last block decided whole is resolved without touching its
/// padding lanes, in a chunk of movable point particles too (whose
/// real lanes take `w` 1 without reading the column).
#[test]
fn the_padding_lanes_of_a_short_last_block_are_left_alone() {
    let dt = 1.0 / 60.0;
    let plane = Plane {
        normal: Vec3::Y,
        ..Plane::default()
    };
    let forces: Vec<Box<dyn Force>> = vec![Box::new(Gravity {
        acceleration: Vec3::new(0.0, -9.81, 0.0),
    })];
    let colliders: Vec<Box<dyn Collider>> = vec![Box::new(plane)];
    let sweep = Sweep::new(&colliders, &[false], &forces, dt, 0.1).expect("an in-step plane");
    let lanes = sweep.plane.expect("a lone plane along an axis");
    // Five rows: block 1 holds row 4, which falls through the floor
    // within the step, and three padding lanes below it.
    let below = Vec3A::new(0.0, -1.0, 0.0);
    let v = Vec3A::new(0.0, -3.0, 0.0);
    let start = [
        Vec3x4::from_lanes([Vec3A::splat(5.0); 4]),
        Vec3x4::from_lanes([Vec3A::new(0.0, 0.02, 0.0), below, below, below]),
    ];
    let mut x = [
        start[0],
        Vec3x4::from_lanes([Vec3A::new(0.0, 0.02, 0.0) + v * dt, below, below, below]),
    ];
    let mut vel = [
        Vec3x4::from_lanes([Vec3A::ZERO; 4]),
        Vec3x4::from_lanes([v, Vec3A::ZERO, Vec3A::ZERO, Vec3A::ZERO]),
    ];
    let (radius, inverse_mass) = ([0.0f32; 5], [1.0f32; 5]);
    let mut chunk = Chunk {
        x: &mut x,
        v: &mut vel,
        radius: &radius,
        inverse_mass: &inverse_mass,
        movable: true,
        point: true,
    };
    // Block 0 settled (clear), block 1: row 4 open, its padding set.
    let mut settled = [0b1111, 0b1110];
    lanes.follow_chunk::<1>(false, true, 0, &start, &mut chunk, &mut settled, &mut Vec::new());
    assert_eq!(settled, [0b1111, 0b1111], "row 4 is decided by the lanes");
    assert!(x[1].lane(0).y >= 0.0, "row 4 bounced off the floor: {}", x[1].lane(0));
    for lane in 1..4 {
        assert_eq!(
            (x[1].lane(lane), vel[1].lane(lane)),
            (below, Vec3A::ZERO),
            "padding lane {lane}"
        );
    }
}

/// Random lanes near planes along each axis and sign, under gravity
/// and drag, stepped by semi-implicit Euler's path (straight) or a
/// parabola: where the lanes decide a lane, its state is `row`'s (in
/// `f64`) to `f32` rounding; most crossing lanes are decided.
#[test]
fn the_lanes_agree_with_the_exact_rule_to_rounding() {
    let mut seed = 0x2545_f491_u32;
    let mut random = move || {
        seed ^= seed << 13;
        seed ^= seed >> 17;
        seed ^= seed << 5;
        (seed >> 8) as f32 / (1u32 << 24) as f32
    };
    let dt = 1.0 / 60.0;
    let (mut decided, mut crossing, mut compared) = (0, 0, 0);
    for case in 0..6_000 {
        let axis = case % 3;
        let negative = case % 2 == 1;
        let sign = if negative { -1.0 } else { 1.0 };
        let mut normal = Vec3::ZERO;
        normal[axis] = sign;
        let material = Material {
            restitution: [0.0, 0.5, 0.8, 1.0][case % 4],
            friction: [0.0, 0.3][(case / 4) % 2],
        };
        let offset = [0.0, 1.5, -3.0][(case / 8) % 3];
        let plane = Plane {
            normal,
            offset,
            material,
            ..Plane::default()
        };
        let mut gravity = Vec3::ZERO;
        gravity[axis] = -9.81 * sign;
        let forces: Vec<Box<dyn Force>> = vec![
            Box::new(Gravity { acceleration: gravity }),
            Box::new(LinearDrag { rate: 0.1 }),
        ];
        let colliders: Vec<Box<dyn Collider>> = vec![Box::new(plane)];
        let rest_speed = [0.0, 0.1, 0.5][(case / 24) % 3];
        let sweep = Sweep::new(&colliders, &[false], &forces, dt, rest_speed).expect("an in-step plane");
        let lanes = sweep.plane.expect("a lone plane along an axis");
        assert_eq!(lanes.plane.axis, axis);
        // Four particles about to meet the plane, or just past it.
        let mut start = [Vec3A::ZERO; 4];
        let mut x = [Vec3A::ZERO; 4];
        let mut v = [Vec3A::ZERO; 4];
        let mut r = [0.0f32; 4];
        for k in 0..4 {
            let speed = [0.05, 1.0, 8.0, 60.0][(case + k) % 4] * (0.5 + random());
            let mut velocity = Vec3A::new(random() - 0.5, random() - 0.5, random() - 0.5) * 4.0;
            velocity[axis] = -sign * speed;
            let radius = if (case + k) % 3 == 0 { 0.0 } else { random() * 0.2 };
            let height = offset + radius + (random() * 1.5 - 0.2) * speed * dt;
            let mut x0 = Vec3A::new(random() * 10.0 - 5.0, random() * 10.0 - 5.0, random() * 10.0 - 5.0);
            x0[axis] = sign * height;
            // Semi-implicit Euler's straight path, or the parabola of
            // a method that carries the acceleration.
            let bend = if (case / 2) % 2 == 0 { 0.0 } else { 0.5 };
            let a = Vec3A::from(gravity);
            let v1 = velocity + a * dt;
            let x1 = x0 + v1 * dt - a * (bend * dt * dt);
            start[k] = x0;
            x[k] = x1;
            v[k] = v1;
            r[k] = radius;
        }
        let (mut xb, mut vb) = (Vec3x4::from_lanes(x), Vec3x4::from_lanes(v));
        let r4 = Vec4::from_array(r);
        let follow = match axis {
            0 => PlaneLanes::follow::<0>,
            1 => PlaneLanes::follow::<1>,
            _ => PlaneLanes::follow::<2>,
        };
        let done = follow(
            &lanes,
            &Vec3x4::from_lanes(start),
            &mut xb,
            &mut vb,
            r4,
            Vec4::ONE,
            0b1111,
        )
        .decided;
        for k in 0..4 {
            let (mut xk, mut vk) = (x[k], v[k]);
            let mut touches = Vec::new();
            let within = sweep.row(k, start[k], &mut xk, &mut vk, r[k], 1.0, &mut touches);
            if within.is_err() {
                // Past the event limit (a ball pinned by restitution
                // 0 with no rest speed): never one the lanes decide.
                assert_eq!(done & (1 << k), 0, "case {case}, lane {k}: decided, but row overflows");
                continue;
            }
            let gap0 = sign * start[k][axis] - offset - r[k];
            let gap1 = sign * x[k][axis] - offset - r[k];
            // A clear crossing that bounces (a bounce of restitution 0
            // meets the surface again, slowly: `row`'s).
            let clear = gap0 > 1e-3 && gap1 < -1e-3 && material.restitution > 0.0 && v[k].length() > 1.0;
            crossing += usize::from(clear);
            if done & (1 << k) == 0 {
                // Left to `row`: nothing changed here.
                assert_eq!((xb.lane(k), vb.lane(k)), (x[k], v[k]), "case {case}, lane {k}");
                continue;
            }
            decided += usize::from(clear);
            compared += 1;
            let scale = 1.0 + vk.length();
            let (dx, dv) = ((xb.lane(k) - xk).length(), (vb.lane(k) - vk).length());
            assert!(
                dx <= 2e-6 * scale && dv <= 4e-5 * scale,
                "case {case}, lane {k}: lanes {} {} against row {xk} {vk} (axis {axis}, sign {sign}, {material:?})",
                xb.lane(k),
                vb.lane(k)
            );
        }
    }
    assert!(compared > 10_000, "{compared} lanes compared");
    assert!(
        decided * 10 > crossing * 9,
        "{decided} of {crossing} clearly crossing, bouncing lanes decided in lanes"
    );
}
