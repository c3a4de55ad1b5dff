//! The plane's fast paths against its general contact.

use super::*;

/// The four-lane path for axis-aligned planes, and the frictionless
/// path, give the same results as the general contact (up to the sign of
/// zero).
#[test]
fn axis_fast_paths_equal_the_general_contact() {
    for friction in [0.3, 0.0] {
        // Every approach bounces, and (a rest speed) the slow ones rest.
        for rest in [0.0, 0.8] {
            axis_fast_path_equals_the_general_contact(friction, rest);
        }
    }
}

fn axis_fast_path_equals_the_general_contact(friction: f32, rest: f32) {
    let material = Material {
        restitution: 0.7,
        friction,
    };
    let mut seed = 12345u32;
    let mut random = || {
        seed = seed.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
        (seed >> 8) as f32 / (1 << 24) as f32 * 2.0 - 1.0
    };
    for (normal, axis) in [(Vec3::Y, 1), (Vec3::NEG_X, 0), (Vec3::Z, 2)] {
        let plane = Plane {
            normal,
            offset: 0.1,
            material,
            ..Plane::default()
        };
        let n = 23; // five blocks of four and a padded tail of three
        let mut x: Vec<Vec3A> = (0..n).map(|_| Vec3A::new(random(), random(), random()) * 0.3).collect();
        let mut v: Vec<Vec3A> = (0..n).map(|_| Vec3A::new(random(), random(), random()) * 3.0).collect();
        let radius: Vec<f32> = (0..n).map(|_| random().abs() * 0.1).collect();
        let inverse_mass: Vec<f32> = (0..n).map(|k| if k % 5 == 0 { 0.0 } else { 1.0 }).collect();
        let (mut x2, mut v2) = (x.clone(), v.clone());
        let nn = Vec3A::from(normal);
        for k in 0..n {
            let gap = nn.dot(x2[k]) - plane.offset - radius[k];
            resolve(&mut x2[k], &mut v2[k], nn, gap, inverse_mass[k] > 0.0, material, rest);
        }
        let columns = ContactColumns {
            position: &mut x,
            velocity: &mut v,
            radius: &radius,
            inverse_mass: &inverse_mass,
            parallel: false,
            max_pairs: u64::MAX,
            start: None,
            rest_speed: rest,
        };
        assert_eq!(axis_of(normal).map(|a| a.0), Some(axis));
        plane.resolve_range(columns);
        assert_eq!(x, x2, "positions, normal {normal}");
        assert_eq!(v, v2, "velocities, normal {normal}");
        assert!(
            x.iter().zip(&radius).any(|(x, r)| (nn.dot(*x) - 0.1 - r).abs() < 1e-6),
            "some contacts"
        );
        // A slow approach rests: on the surface, no normal velocity.
        let rested = (0..n).any(|k| (nn.dot(x[k]) - 0.1 - radius[k]).abs() < 1e-6 && nn.dot(v[k]) == 0.0);
        assert_eq!(rested, rest > 0.0, "rest speed {rest}, normal {normal}");
    }
    assert_eq!(axis_of(Vec3::new(0.6, 0.8, 0.0)), None);
}

/// A lane whose `v dt` passes the resting test's bound while `v` is
/// past the rest speed by a rounding: the resting chunk must not
/// resolve it without its bounce, as the end-of-step rule gives it.
#[test]
fn a_resting_chunk_is_resolved_as_the_end_of_step_rule_resolves_it_at_the_rest_speeds_edge() {
    // (A rest speed of a power of two, as the default 0.5, scales
    // exactly: no such edge.)
    let edge = (1..400).map(|k| 0.1 + k as f32 * 0.0137).find_map(|rest| {
        [1.0f32 / 60.0, 1.0 / 30.0, 1.0 / 240.0, 0.01, 0.003]
            .into_iter()
            .find_map(|dt| {
                let mut vn = -rest;
                for _ in 0..256 {
                    vn = f32::from_bits(vn.to_bits() + 1);
                    if vn * dt >= -(rest * dt) && vn < -rest {
                        return Some((rest, dt, vn));
                    }
                }
                None
            })
    });
    let (rest, dt, edge) = edge.expect("a rest speed and step whose rounding puts v dt inside the bound, v outside");
    let plane = Plane::floor(
        0.0,
        Material {
            restitution: 0.7,
            friction: 0.0,
        },
    );
    // Eight blocks on the floor, each particle at y = 0 at the start
    // and sinking at -0.1 m/s (resting), one at the edge speed.
    let blocks = 8;
    let lanes = |y: f32| Vec3x4 {
        x: Vec4::ZERO,
        y: Vec4::splat(y),
        z: Vec4::ZERO,
    };
    let start = vec![lanes(0.0); blocks];
    let mut v = vec![lanes(-0.1); blocks];
    v[5].y = Vec4::new(-0.1, edge, -0.1, -0.1);
    let mut x: Vec<Vec3x4> = v
        .iter()
        .map(|v| Vec3x4 {
            x: Vec4::ZERO,
            y: v.y * dt,
            z: Vec4::ZERO,
        })
        .collect();
    let (mut x_end, mut v_end) = (x.clone(), v.clone());
    for (x, v) in x_end.iter_mut().zip(v_end.iter_mut()) {
        plane.contact_block::<1, false>(x, v, Vec4::ZERO, Vec4::ONE, rest);
    }
    assert!(v_end[5].y.y > 0.0, "the edge lane bounces by the end-of-step rule");
    let (radius, inverse_mass) = (vec![0.0; blocks * 4], vec![1.0; blocks * 4]);
    let mut settled = vec![0b1111u8; blocks];
    let columns = BlockColumns {
        position: &mut x,
        velocity: &mut v,
        radius: &radius,
        inverse_mass: &inverse_mass,
        rows: blocks * 4,
        movable: true,
        point: true,
        rest_speed: rest,
    };
    assert!(plane.settle_blocks(&start, columns, dt, true, &mut settled));
    // Every block as the end-of-step rule left it: the edge lane's
    // bounces (its block taken block by block, whole blocks of
    // resting lanes resolved by the rule's own test).
    for b in 0..blocks {
        assert_eq!((x[b], v[b]), (x_end[b], v_end[b]), "block {b}");
    }
}

#[test]
fn a_particle_gets_the_same_bits_in_a_block_of_four_and_in_the_tail() {
    // Which path a particle takes depends on the particles around it
    // (its place in the chunk); its result must not. Resting, sinking,
    // rising, -0 and NaN velocities, an immovable particle.
    let plane = Plane::floor(
        0.0,
        Material {
            restitution: 0.6,
            friction: 0.0,
        },
    );
    let x = [0.01, -0.02, 0.03, -0.0, 0.5, -0.3, f32::NAN, 0.02].map(|y| Vec3A::new(0.1, y, -0.2));
    let v = [-0.0, -1.0, 2.0, -3.0, 0.0, f32::NAN, -1.0, -0.5].map(|y| Vec3A::new(0.3, y, 0.0));
    let radius = [0.02; 8];
    let inverse_mass = [1.0, 1.0, 1.0, 1.0, 1.0, 1.0, 1.0, 0.0];
    let (mut xb, mut vb) = (x, v);
    plane.resolve_range(ContactColumns {
        position: &mut xb,
        velocity: &mut vb,
        radius: &radius,
        inverse_mass: &inverse_mass,
        parallel: false,
        max_pairs: u64::MAX,
        start: None,
        rest_speed: 0.0,
    });
    for k in 0..8 {
        let (mut xt, mut vt) = ([x[k]], [v[k]]);
        plane.resolve_range(ContactColumns {
            position: &mut xt,
            velocity: &mut vt,
            radius: &radius[k..=k],
            inverse_mass: &inverse_mass[k..=k],
            parallel: false,
            max_pairs: u64::MAX,
            start: None,
            rest_speed: 0.0,
        });
        let bits = |a: Vec3A| a.to_array().map(f32::to_bits);
        assert_eq!(bits(xb[k]), bits(xt[0]), "position {k}");
        assert_eq!(bits(vb[k]), bits(vt[0]), "velocity {k}");
    }
    assert!(xb[1].y > 0.0 && vb[1].y > 0.0, "a sinking particle bounces");
}
