//! Scene files: every shipped scene loads and runs; malformed scenes give
//! errors with file, line, column, field and what was expected.

use std::path::PathBuf;

use tickwork_engine::{FixedClock, Scene, SceneError};

fn scenes_dir() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../assets/scenes")
}

#[test]
fn every_shipped_scene_loads_builds_and_steps() {
    let mut names = Vec::new();
    for entry in std::fs::read_dir(scenes_dir()).expect("assets/scenes") {
        let path = entry.expect("entry").path();
        if path.extension().is_none_or(|e| e != "ron") {
            continue;
        }
        let scene = Scene::load(&path).unwrap_or_else(|e| panic!("{e}"));
        let (mut world, _) = scene.build().unwrap_or_else(|e| panic!("{e}"));
        let mut clock = FixedClock::default();
        clock.set_rate(scene.rate().expect("rate"));
        for step in clock.step(10).fixed_steps() {
            world.step(step).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        }
        names.push(scene.name());
    }
    names.sort();
    assert_eq!(
        names,
        [
            "bouncing ball",
            "crowd",
            "fountain",
            "kepler",
            "pendulum chain",
            "projectile",
            "rain",
            "tops"
        ]
        .map(String::from)
    );
}

fn parse_error(text: &str) -> SceneError {
    Scene::parse(text, "bad.ron").expect_err("malformed")
}

#[test]
fn malformed_scenes_name_file_line_column_and_field() {
    let cases = [
        (
            "SceneFile(\n  particles: [\n    (position: (0, 1, 0)),\n    (position: (0, 2, 0), mass: -1),\n  ],\n)",
            "bad.ron:4:33: particles[1].mass: expected a finite number above zero, got -1",
        ),
        (
            "SceneFile(integrator: \"rk5\")",
            "bad.ron:1:24: integrator: unknown integrator 'rk5'; valid names are: explicit_euler,",
        ),
        (
            "SceneFile(colour: 3)",
            "bad.ron:1:11: colour: Unexpected field named `colour` in `SceneFile`, expected one of `name`",
        ),
        (
            "SceneFile(forces: [Gravity((0, NaN, 0))])",
            "bad.ron:1:38: forces[0].Gravity: expected finite coordinates, got NaN for y",
        ),
        (
            "SceneFile(\n  forces: [Spring(a: Particle(0), b: Particle(2), stiffness: 1, rest_length: 1)],\n  particles: [(position: (0, 0, 0)), (position: (1, 0, 0))],\n)",
            "bad.ron:2:47: forces[0].Spring.b.Particle: particle index 2 is out of range: the scene lists 2 particles",
        ),
        (
            "SceneFile(rate: Hz(0))",
            "bad.ron:1:20: rate.Hz: expected a finite number above zero, got 0",
        ),
        ("SceneFile(particles: [(position: (0, 0))])", "bad.ron:1:"),
        ("SceneFile(seed: 1", "bad.ron:1:17: Expected comma"),
        (
            "SceneFile(colliders: [Plane(normal: (0, 1, 0), material: (restitution: 1.5))])",
            "bad.ron:1:72: colliders[0].Plane.material.restitution: expected a number from 0 to 1, got 1.5",
        ),
    ];
    let mut wrong = Vec::new();
    for (text, expected) in cases {
        let message = parse_error(text).to_string();
        if !message.starts_with(expected) {
            wrong.push(format!("got:      {message}\nexpected: {expected}"));
        }
    }
    assert!(wrong.is_empty(), "{}", wrong.join("\n"));
}

#[test]
fn scene_errors_carry_their_parts() {
    let err = parse_error("SceneFile(\n  particles: [(position: (0, 1, 0), radius: -0.5)],\n)");
    assert_eq!(err.file, "bad.ron");
    assert_eq!(err.field, "particles[0].radius");
    assert_eq!(err.position.map(|p| p.0), Some(2));
    let missing = Scene::load(&scenes_dir().join("no-such-scene.ron")).expect_err("missing");
    assert!(
        missing
            .to_string()
            .contains("no-such-scene.ron: cannot read the scene:"),
        "{missing}"
    );
}

#[test]
fn a_zero_plane_normal_is_an_error() {
    // Refused while read, with its line and column (it once waited for the
    // build, which has no position to give).
    let err = Scene::parse("SceneFile(colliders: [Plane(normal: (0, 0, 0))])", "z.ron").expect_err("zero normal");
    assert_eq!(
        err.to_string(),
        "z.ron:1:45: colliders[0].Plane.normal: expected a direction of non-zero, finite length, got [0.0, 0.0, 0.0]"
    );
}

#[test]
fn misspelt_fields_and_bad_values_inside_forces_and_colliders_are_errors() {
    let cases = [
        // Misspelt fields were silently ignored inside variants.
        (
            "SceneFile(forces: [Attractor(position: (0, 0, 0), gm: 1, softning: 0.5)])",
            "bad.ron:1:",
            "softning",
        ),
        (
            "SceneFile(colliders: [Plane(normal: (0, 1, 0), ofset: 2.0)])",
            "bad.ron:1:",
            "ofset",
        ),
        (
            "SceneFile(colliders: [Plane(normal: (0, 1, 0), material: (restitution: 0.5), materail: ())])",
            "bad.ron:1:",
            "materail",
        ),
        // A NaN or infinite offset made the floor inert (or blamed the step size).
        (
            "SceneFile(colliders: [Plane(normal: (0, 1, 0), offset: NaN)])",
            "bad.ron:1:",
            "colliders[0].Plane.offset: expected a finite number, got NaN",
        ),
        (
            "SceneFile(colliders: [Plane(normal: (0, 1, 0), offset: inf)])",
            "bad.ron:1:",
            "colliders[0].Plane.offset: expected a finite number, got inf",
        ),
        // A normal whose length overflows was reported as "zero length".
        (
            "SceneFile(colliders: [Plane(normal: (3e38, 3e38, 0))])",
            "bad.ron:1:",
            "colliders[0].Plane.normal: expected a direction of non-zero, finite length",
        ),
    ];
    let mut wrong = Vec::new();
    for (text, start, contains) in cases {
        let message = parse_error(text).to_string();
        if !(message.starts_with(start) && message.contains(contains)) {
            wrong.push(format!("got:      {message}\nexpected: {start}... {contains}"));
        }
    }
    assert!(wrong.is_empty(), "{}", wrong.join("\n"));
}

#[test]
fn resource_demands_past_a_limit_are_errors_naming_the_limit() {
    let err = parse_error("SceneFile(lattices: [(origin: (0, 0, 0), count: (1000, 1000, 1000), spacing: 0.1)])");
    let message = err.to_string();
    assert!(message.starts_with("bad.ron:1:"), "{message}");
    assert!(
        message.contains(
            "lattices[0].count: expected at most 10000000 particles in a lattice (MAX_LATTICE_PARTICLES), \
             got 1000 x 1000 x 1000 = 1000000000; split it into several lattices"
        ),
        "{message}"
    );
    // A file that never ends (Linux's /dev/zero) is read only to the limit.
    let err = Scene::load(std::path::Path::new("/dev/zero")).expect_err("endless");
    assert_eq!(
        err.to_string(),
        "/dev/zero: cannot read the scene: it is larger than the limit of 16777216 bytes \
         (Scene::MAX_FILE_BYTES); a scene this large is better built by a program"
    );
}
