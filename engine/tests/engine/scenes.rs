//! Scene files: every shipped scene loads and runs; malformed scenes give
//! errors with file, line, column, field and what was expected.

use std::path::PathBuf;

use tickwork_engine::{BoxCollider, ContactRule, FixedClock, Plane, Scene, SceneError, World, WorldConfig};

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
            "bounce rules",
            "bouncing ball",
            "crowd",
            "downpour",
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
        // An inverted box was accepted (and pushed every particle out).
        (
            "SceneFile(colliders: [Plane(normal: (0, 1, 0)),\n  Box(min: (1, 1, 1), max: (-1, -1, -1))])",
            "bad.ron:2:40: colliders[1]: ",
            "Box.max.x = -1 is not above Box.min.x = 1",
        ),
        (
            "SceneFile(colliders: [Box(min: (-3e38, 0, 0), max: (3e38, 1, 1))])",
            "bad.ron:1:",
            "colliders[0]: Box from min.x = -3e38 to max.x = 3e38: expected a width that is a finite number",
        ),
        // A zero emitter direction silently became +y.
        (
            "SceneFile(emitters: [(position: (0, 0, 0), direction: (0, 0, 0), speed: 1, rate: 1, lifetime: 1)])",
            "bad.ron:1:",
            "emitters[0].direction: expected a direction of non-zero, finite length",
        ),
        // Rigid bodies: a zero quaternion, negative or degenerate extents, an
        // inertia whose inverse overflows; once only found by the build, with no position.
        (
            "SceneFile(rigid_bodies: [(particle: (position: (0, 0, 0)), orientation: (0, 0, 0, 0), half_extents: (1, 1, 1))])",
            "bad.ron:1:",
            "rigid_bodies[0].orientation: expected a quaternion (x, y, z, w) of finite coordinates and non-zero",
        ),
        (
            "SceneFile(rigid_bodies: [(particle: (position: (0, 0, 0)), half_extents: (1, -1, 1))])",
            "bad.ron:1:",
            "rigid_bodies[0]: half_extents.y = -1: expected half extents that are not negative",
        ),
        (
            "SceneFile(rigid_bodies: [(particle: (position: (0, 0, 0)), half_extents: (1, 0, 0))])",
            "bad.ron:1:",
            "rigid_bodies[0]: half_extents (1, 0, 0) and mass 1 give the moment of inertia inertia.x = 0: expected",
        ),
        (
            "SceneFile(rigid_bodies: [(particle: (position: (0, 0, 0), mass: 1e30), half_extents: (1e10, 1, 1))])",
            "bad.ron:1:",
            "rigid_bodies[0]: half_extents (1e10, 1, 1) and mass 1e30 give the moment of inertia inertia.y = inf: expected",
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
    // Lattices each under their limit, together past the world's: refused
    // before a particle is allocated.
    let two = "SceneFile(lattices: [\
        (origin: (0, 0, 0), count: (1000, 1000, 10), spacing: 0.1),\
        (origin: (0, 0, 5), count: (1000, 1000, 10), spacing: 0.1)])";
    let scene = Scene::parse(two, "two.ron").expect("each lattice is within its limit");
    let err = scene.build().expect_err("past the world's limit");
    assert_eq!(
        err.to_string(),
        "two.ron: the scene holds 20000000 particles, past the world's limit of 10000000 \
         (WorldConfig::max_particles); build it with Scene::build_with and a higher limit"
    );
    let small = WorldConfig {
        max_particles: 15,
        ..scene.world_config()
    };
    let four = Scene::parse(
        "SceneFile(lattices: [(origin: (0, 0, 0), count: (4, 4, 1), spacing: 0.1)])",
        "four.ron",
    )
    .expect("a small lattice");
    assert!(
        four.build_with(small.clone())
            .expect_err("16 > 15")
            .to_string()
            .contains("holds 16 particles")
    );
    assert_eq!(
        four.build_with(WorldConfig {
            max_particles: 16,
            ..small
        })
        .expect("fits")
        .0
        .len(),
        16
    );
    // A file that never ends (Linux's /dev/zero) is read only to the limit.
    let err = Scene::load(std::path::Path::new("/dev/zero")).expect_err("endless");
    assert_eq!(
        err.to_string(),
        "/dev/zero: cannot read the scene: it is larger than the limit of 16777216 bytes \
         (Scene::MAX_FILE_BYTES); a scene this large is better built by a program"
    );
}

/// The rules of the world's planes and boxes, in the order they were
/// added (other colliders have none).
fn contact_rules(world: &World) -> Vec<ContactRule> {
    world
        .colliders()
        .filter_map(|(id, _)| {
            world
                .collider::<Plane>(id)
                .map(|plane| plane.contact)
                .or_else(|_| world.collider::<BoxCollider>(id).map(|b| b.contact))
                .ok()
        })
        .collect()
}

#[test]
fn a_collider_s_contact_rule_is_carried_into_the_world_and_defaults_to_in_step() {
    use ContactRule::{EndOfStep, InStep};
    let text = "SceneFile(colliders: [\
        Plane(normal: (0, 1, 0), contact: InStep),\
        Box(min: (-1, -1, -1), max: (1, 1, 1), inside: false, contact: InStep),\
        Plane(normal: (1, 0, 0), contact: EndOfStep),\
        Box(min: (-1, -1, -1), max: (1, 1, 1), contact: EndOfStep),\
        Plane(normal: (0, 0, 1)),\
        Box(min: (-1, -1, -1), max: (1, 1, 1)),\
        Spheres(),\
    ])";
    let scene = Scene::parse(text, "rules.ron").expect("a valid scene");
    let (world, _) = scene.build().expect("builds");
    let rules = contact_rules(&world);
    assert_eq!(rules, [InStep, InStep, EndOfStep, EndOfStep, InStep, InStep]);
    // The shipped scenes that do not name a rule find contacts in the step.
    let mut planes_and_boxes = 0;
    for entry in std::fs::read_dir(scenes_dir()).expect("assets/scenes") {
        let path = entry.expect("entry").path();
        let text = std::fs::read_to_string(&path).expect("readable");
        if path.extension().is_none_or(|e| e != "ron") || text.contains("contact:") {
            continue;
        }
        let scene = Scene::parse(&text, "shipped.ron").unwrap_or_else(|e| panic!("{e}"));
        let rules = contact_rules(&scene.build().unwrap_or_else(|e| panic!("{e}")).0);
        assert!(rules.iter().all(|&r| r == InStep), "{}: {rules:?}", path.display());
        planes_and_boxes += rules.len();
    }
    assert!(planes_and_boxes > 0, "a shipped scene has a plane or a box");
}

#[test]
fn a_misspelt_contact_rule_names_the_field_the_accepted_rules_and_where() {
    let err = parse_error("SceneFile(colliders: [Plane(normal: (0, 1, 0), contact: Instep)])");
    assert_eq!(
        err.to_string(),
        "bad.ron:1:57: colliders[0].Plane.contact: Unexpected variant named `Instep` in enum `ContactSpec`, \
         expected either `EndOfStep` or `InStep` instead"
    );
    let err = parse_error("SceneFile(colliders: [\n  Box(min: (0, 0, 0), max: (1, 1, 1), contact: end_of_step)])");
    assert_eq!(err.field, "colliders[0].Box.contact");
    assert_eq!(err.position, Some((2, 48)));
    assert!(
        err.to_string().contains("expected either `EndOfStep` or `InStep`"),
        "{err}"
    );
}

#[test]
fn sphere_collisions_are_swept_when_the_scene_says_so() {
    for (text, swept) in [
        ("SceneFile(colliders: [Spheres(swept: true)])", true),
        ("SceneFile(colliders: [Spheres(material: (restitution: 0.3))])", false),
    ] {
        let scene = Scene::parse(text, "spheres.ron").expect("a valid scene");
        let (world, _) = scene.build().expect("builds");
        let found: Vec<bool> = world
            .colliders()
            .filter_map(|(_, c)| c.as_any().downcast_ref::<tickwork_engine::SphereCollisions>())
            .map(|s| s.swept)
            .collect();
        assert_eq!(found, [swept], "{text}");
    }
    let error = Scene::parse("SceneFile(colliders: [Spheres(swept: 1)])", "bad.ron").expect_err("not a bool");
    assert!(error.to_string().starts_with("bad.ron:1:"), "{error}");
}
