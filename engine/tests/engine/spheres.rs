//! The sphere broad phase on hostile input: particles a billion metres apart,
//! a diverging scene, and mixed sizes (one big ball among grains), against a
//! brute-force count of the touching pairs; and the parallel slabs, the same
//! on any number of threads.
// Reference values and set-ups computed natively (never in a page): the
// platform's own functions are fine here (clippy.toml bans them in the engine).
#![allow(clippy::disallowed_methods)]

use glam::Vec3;
use tickwork_engine::clock::FixedStep;
use tickwork_engine::{
    Collider, Material, Particle, SimulationError, SphereCollisions, Spring, SpringEnd, Springs, World, WorldConfig,
};

fn step(w: &mut World) -> Result<(), SimulationError> {
    let tick = w.tick();
    w.step(FixedStep {
        tick,
        time: tick as f64 / 60.0,
        dt: 1.0 / 60.0,
    })
    .map(|_| ())
}

/// The world's sphere collider.
fn spheres(w: &mut World) -> &SphereCollisions {
    w.colliders()
        .find_map(|(_, c)| c.as_any().downcast_ref::<SphereCollisions>())
        .expect("a sphere collider")
}

/// Contacts resolved by the last step.
fn contacts(w: &mut World) -> usize {
    spheres(w).contacts()
}

#[test]
fn particles_a_billion_metres_apart_just_work() {
    let mut w = World::new(WorldConfig::default()).expect("default");
    w.add_collider(SphereCollisions::new(Material::default()));
    for x in [1e9, -1e9, 3e38, -3e38] {
        w.spawn(Particle {
            position: Vec3::new(x, 0.0, 0.0),
            ..Particle::default()
        })
        .expect("valid");
    }
    // Two that touch, far from the origin: still found.
    for x in [2e6, 2e6 + 0.05] {
        w.spawn(Particle {
            position: Vec3::new(x, 5.0, 0.0),
            ..Particle::default()
        })
        .expect("valid");
    }
    for _ in 0..3 {
        step(&mut w).expect("finite far-apart particles step");
    }
    assert_eq!(contacts(&mut w), 0, "the touching pair separated on the first step");
}

#[test]
fn a_diverging_scene_with_spheres_is_a_non_finite_error_not_a_panic() {
    // Explicit Euler on stiff springs at 60 Hz blows up.
    let mut w = World::new(WorldConfig {
        integrator: "explicit_euler".into(),
        ..WorldConfig::default()
    })
    .expect("registered");
    w.add_collider(SphereCollisions::new(Material::default()));
    let mut springs = Vec::new();
    let mut previous = None;
    for k in 0..10 {
        let e = w
            .spawn(Particle {
                position: Vec3::new(k as f32 * 0.2, 0.0, 0.0),
                velocity: Vec3::new(0.0, (k % 3) as f32, 0.0),
                ..Particle::default()
            })
            .expect("valid");
        if let Some(p) = previous {
            springs.push(Spring {
                a: SpringEnd::Entity(p),
                b: SpringEnd::Entity(e),
                stiffness: 5e4,
                rest_length: 0.2,
                damping: 0.0,
            });
        }
        previous = Some(e);
    }
    w.add_force(Springs::new(springs));
    let error = (0..2_000).find_map(|_| step(&mut w).err()).expect("the scene diverges");
    assert!(
        matches!(error, SimulationError::NonFinite { .. }),
        "expected a non-finite error, got {error}"
    );
    assert!(error.to_string().contains("non-finite"), "{error}");
}

/// A ball of radius 5 at the origin; grains of radius 0.05 placed so that no
/// contact moves a grain into another one: some just inside the ball's
/// surface (one contact each), some in isolated touching pairs, the rest
/// alone. Returns the world and the number of touching pairs.
fn ball_among_grains(grains: usize) -> (World, usize) {
    let mut w = World::new(WorldConfig::default()).expect("default");
    w.add_collider(SphereCollisions::new(Material {
        restitution: 0.5,
        friction: 0.0,
    }));
    w.spawn(Particle {
        position: Vec3::ZERO,
        radius: 5.0,
        mass: 1e6,
        ..Particle::default()
    })
    .expect("valid");
    let mut touching = 0;
    for k in 0..grains {
        // Directions spread over the sphere (a golden-angle spiral).
        let z = 1.0 - 2.0 * (k as f32 + 0.5) / grains as f32;
        let phi = k as f32 * 2.399_963;
        let dir = Vec3::new((1.0 - z * z).sqrt() * phi.cos(), (1.0 - z * z).sqrt() * phi.sin(), z);
        let position = match k % 4 {
            0 => {
                touching += 1;
                dir * 5.04
            }
            1 => dir * (20.0 + (k % 97) as f32 * 0.5),
            2 => {
                touching += 1;
                w.spawn(Particle {
                    position: dir * 40.0 + Vec3::X * 0.09,
                    radius: 0.05,
                    ..Particle::default()
                })
                .expect("valid");
                dir * 40.0
            }
            _ => dir * 60.0,
        };
        w.spawn(Particle {
            position,
            radius: 0.05,
            ..Particle::default()
        })
        .expect("valid");
    }
    (w, touching)
}

#[test]
fn one_big_ball_among_grains_finds_every_contact_once() {
    let (mut w, touching) = ball_among_grains(4_000);
    // Brute force over every pair of the start state agrees.
    let p = w.particles();
    let n = p.len();
    let mut brute = 0;
    for i in 0..n {
        for j in i + 1..n {
            let reach = p.radius[i] + p.radius[j];
            let (a, b) = (p.position.get(i).expect("row"), p.position.get(j).expect("row"));
            if (a - b).length_squared() < reach * reach {
                brute += 1;
            }
        }
    }
    assert_eq!(brute, touching, "the constructed scene");
    step(&mut w).expect("step");
    assert_eq!(contacts(&mut w), touching);
}

#[test]
fn mixed_sizes_cost_about_as_much_as_one_size() {
    // The broad phase's work, counted as candidate pairs it tested (not
    // timed). With one cell size set by the ball, the 20 000 grains in 5 000
    // isolated places would share a few hundred huge cells: millions of
    // candidates. The hierarchical grid keeps it a small multiple of n.
    let (mut mixed, _) = ball_among_grains(20_000);
    step(&mut mixed).expect("step");
    let n = mixed.particles().len();
    let tested = spheres(&mut mixed).pairs_tested();
    println!("{n} spheres, {tested} candidate pairs tested");
    assert!(tested < 4 * n, "{tested} candidate pairs for {n} spheres");
}

/// A packed crowd of grains of radius 0.045 (the crowd scene's), in
/// touching pairs along x, 0.3 m apart otherwise, plus `giants` (radius,
/// x) far from them. Returns the world and the touching pairs.
fn grains_and_giants(side: usize, giants: &[(f32, f32)]) -> (World, usize) {
    let mut w = World::new(WorldConfig::default()).expect("default");
    w.add_collider(SphereCollisions::new(Material::default()));
    let mut pairs = 0;
    for i in 0..side {
        for j in 0..side {
            let at = Vec3::new(i as f32 * 0.3, j as f32 * 0.3, 0.0);
            for dx in [0.0, 0.08] {
                w.spawn(Particle {
                    position: at + Vec3::X * dx,
                    radius: 0.045,
                    ..Particle::default()
                })
                .expect("valid");
            }
            pairs += 1;
        }
    }
    for &(radius, x) in giants {
        w.spawn(Particle {
            position: Vec3::new(x, 0.0, 0.0),
            radius,
            mass: 1e6,
            ..Particle::default()
        })
        .expect("valid");
    }
    (w, pairs)
}

#[test]
fn spheres_of_any_size_ratio_keep_the_broad_phase_linear() {
    // Before: a grid of 24 levels put grains 2^100 times smaller than the
    // biggest sphere all in its finest level's cells, 2.4e23 m wide: every
    // pair of grains a candidate (a 100 000-grain crowd took over 10 s a
    // step). Now each size has its level.
    let side = 100;
    let (mut alone, pairs) = grains_and_giants(side, &[]);
    step(&mut alone).expect("step");
    let baseline = spheres(&mut alone).pairs_tested();
    assert_eq!(contacts(&mut alone), pairs);
    for giants in [
        // Two of radius 1e30 (the hardening issue's case), far off.
        vec![(1e30, 1e31), (1e30, -1e31)],
        // A ball 2^25 times a grain's radius (past the f32 levels).
        vec![(1.5e6, 1e8)],
        // The largest f32 radius and the smallest grains' ratio.
        vec![(3e38, 3.4e38)],
    ] {
        let (mut w, pairs) = grains_and_giants(side, &giants);
        step(&mut w).expect("step");
        let n = w.particles().len();
        let tested = spheres(&mut w).pairs_tested();
        assert_eq!(
            contacts(&mut w),
            pairs,
            "every touching pair of grains, with giants {giants:?}"
        );
        assert!(
            tested <= baseline + 2 * n,
            "with giants {giants:?}: {tested} candidate pairs, {baseline} without them, for {n} spheres"
        );
    }
}

#[test]
fn a_grain_inside_a_sphere_a_hundred_million_times_bigger_is_found() {
    // Past the f32 levels (ratio 2^27), placed in f64. (At such a ratio a
    // grain on the surface is below the f32 resolution of the distance, so
    // the grain that touches is well inside.)
    let mut w = World::new(WorldConfig::default()).expect("default");
    w.add_collider(SphereCollisions::new(Material::default()));
    let big = 4_194_304.0f32; // 2^22 m
    w.spawn(Particle {
        radius: big,
        mass: 1e9,
        ..Particle::default()
    })
    .expect("valid");
    for (x, y) in [(1000.0, -3e6), (0.0, 8_388_608.0), (-5e6, 0.0)] {
        w.spawn(Particle {
            position: Vec3::new(x, y, 0.0),
            radius: 0.031_25,
            ..Particle::default()
        })
        .expect("valid");
    }
    step(&mut w).expect("step");
    assert_eq!(
        contacts(&mut w),
        1,
        "the grain inside the ball touches it, the two outside do not"
    );
}

/// Runs `f` on a rayon pool of `threads` threads.
fn on_threads<T: Send>(threads: usize, f: impl FnOnce() -> T + Send) -> T {
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .expect("a pool")
        .install(f)
}

/// 3 600 isolated touching pairs (7 200 spheres, above
/// the default `parallel_threshold`) on a lattice dense enough for the dense grid, each
/// pair 0.09 m apart along z so that many straddle a plane of cells, and
/// with 88 planes, the boundaries between slabs.
fn pairs_along_z() -> World {
    let mut w = World::new(WorldConfig::default()).expect("default");
    w.add_collider(SphereCollisions::new(Material {
        restitution: 0.5,
        friction: 0.0,
    }));
    for a in 0..30 {
        for b in 0..3 {
            for k in 0..40 {
                let at = Vec3::new(a as f32, b as f32, k as f32) * 0.22 + Vec3::splat(0.003 * (k % 7) as f32);
                for dz in [0.0, 0.09] {
                    w.spawn(Particle {
                        position: at + Vec3::Z * dz,
                        radius: 0.05,
                        ..Particle::default()
                    })
                    .expect("valid");
                }
            }
        }
    }
    w
}

#[test]
fn pairs_across_slab_boundaries_are_found_once_on_any_number_of_threads() {
    let mut states = Vec::new();
    for threads in [1, 2, 3] {
        let mut w = pairs_along_z();
        assert!(w.particles().len() >= WorldConfig::default().parallel_threshold);
        on_threads(threads, || step(&mut w)).expect("step");
        let s = spheres(&mut w);
        assert_eq!(s.contacts(), 3_600, "{threads} threads: every pair once");
        // The dense grid, 87 planes of cells in slabs of two.
        assert_eq!(s.slabs(), 44, "slabs");
        assert!(s.slabs() <= SphereCollisions::SLABS);
        states.push((s.pairs_tested(), w.state_hash()));
    }
    assert!(states.windows(2).all(|w| w[0] == w[1]), "{states:?}");
}

#[test]
fn a_settling_pile_is_bit_identical_on_one_two_and_three_threads() {
    // 20 x 18 x 20 spheres packed closer than their diameter, falling onto
    // each other in a box: every sphere touches several, every step.
    // Also on two threads with the world kept to one (`parallel_threshold`).
    let pile = |parallel_threshold| {
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../assets/scenes/crowd.ron");
        let text = std::fs::read_to_string(path).expect("the crowd scene");
        let text = text.replace("count: (100, 10, 100)", "count: (20, 18, 20)");
        let scene = tickwork_engine::Scene::parse(&text, "crowd.ron").expect("parses");
        let config = WorldConfig {
            parallel_threshold,
            ..scene.world_config()
        };
        scene.build_with(config).expect("builds").0
    };
    let mut hashes = Vec::new();
    for (threads, threshold) in [(1, 4_096), (2, 4_096), (3, 4_096), (2, usize::MAX)] {
        let mut w = pile(threshold);
        on_threads(threads, || {
            for _ in 0..60 {
                step(&mut w).expect("step");
            }
        });
        assert!(contacts(&mut w) > 7_200, "{} contacts", contacts(&mut w));
        hashes.push(w.state_hash());
    }
    assert_eq!(hashes[0], hashes[1], "1 and 2 threads");
    assert_eq!(hashes[0], hashes[2], "1 and 3 threads");
    assert_eq!(hashes[0], hashes[3], "2 threads, the world on one");
}

/// `side`^3 grains 0.1 m apart, of radius `radius`.
fn lattice(config: WorldConfig, side: usize, radius: f32) -> World {
    let mut w = World::new(config).expect("valid config");
    w.add_collider(SphereCollisions::new(Material::default()));
    for i in 0..side {
        for j in 0..side {
            for k in 0..side {
                w.spawn(Particle {
                    position: Vec3::new(i as f32, j as f32, k as f32) * 0.1,
                    radius,
                    ..Particle::default()
                })
                .expect("valid");
            }
        }
    }
    w
}

#[test]
fn grains_that_all_overlap_are_an_error_naming_the_pair_limit_not_quadratic_work() {
    // Before: every grain overlapping every other (the fuzzer's crowd of
    // 100 000 with radius 9.2e18) was tested pair by pair, 5e9 pairs a
    // step, with no word. Now the pairs sharing a cell are counted before
    // any is tested, against WorldConfig::max_pairs.
    let config = WorldConfig {
        max_pairs: 1_000_000,
        ..WorldConfig::default()
    };
    let n = 12 * 12 * 12;
    let all_pairs = (n * (n - 1) / 2) as u64;
    assert!(all_pairs > config.max_pairs);
    let mut w = lattice(config.clone(), 12, 1e3);
    let before = w.state_hash();
    let error = step(&mut w).expect_err("past the limit");
    assert_eq!(
        error,
        SimulationError::ContactPairLimit {
            tick: 0,
            collider: "spheres",
            index: 0,
            particles: n,
            pairs: all_pairs,
            limit: 1_000_000,
        }
    );
    assert_eq!(
        error.to_string(),
        format!(
            "step 0: collider 0 (spheres) would test at least {all_pairs} candidate pairs among {n} particles, \
             past the limit of 1000000 (WorldConfig::max_pairs): the spheres are crowded into the same grid \
             cells (overlapping one another, or piled together by another collider); give them room, smaller \
             radii, or raise the limit"
        )
    );
    assert_eq!(spheres(&mut w).refused_pairs(), Some(all_pairs));
    assert_eq!(spheres(&mut w).pairs_tested(), 0, "no pair was tested");
    assert_eq!(w.tick(), 0, "the step did not complete");
    assert_ne!(
        w.state_hash(),
        before,
        "the world is left as the step made it (integrated)"
    );

    // Raised, the same world steps, testing every pair.
    let mut w = lattice(
        WorldConfig {
            max_pairs: all_pairs,
            ..config
        },
        12,
        1e3,
    );
    step(&mut w).expect("within the raised limit");
    assert_eq!(spheres(&mut w).refused_pairs(), None);
    assert_eq!(spheres(&mut w).pairs_tested() as u64, all_pairs);
    assert!(contacts(&mut w) > 0);
}

#[test]
fn a_packed_lattice_is_far_below_the_default_pair_limit() {
    // Grains touching their six neighbours (radius 0.05, 0.1 apart): each
    // cell of the grid (0.1 wide) holds one or two, so the pairs sharing a
    // cell are about n, not n^2; the default limit leaves room for a
    // hundred million such grains.
    let mut w = lattice(WorldConfig::default(), 20, 0.05);
    for _ in 0..10 {
        step(&mut w).expect("a packed lattice steps");
    }
    assert_eq!(spheres(&mut w).refused_pairs(), None);
    assert!(contacts(&mut w) > 0, "the grains touch");
}
