//! Determinism: recorded per-tick inputs replay to a bit-identical state,
//! whatever the frame timing and the number of threads; a press reaches the
//! tick of its time whatever the frame timing; and the fused, parallel step
//! equals the plain one.

use crate::support;
use glam::Vec3;
use tickwork_engine::clock::{FixedCadence, JitteryCadence, TimeSource};
use tickwork_engine::{
    Emitter, Entity, FixedClock, Gravity, InputEvent, InputQueue, Key, LinearDrag, Material, Particle, Plane,
    Recording, TickInput, World, WorldConfig,
};

fn scene(threads_threshold: usize) -> (World, Entity) {
    let mut w = World::new(WorldConfig {
        seed: 7,
        parallel_threshold: threads_threshold,
        ..WorldConfig::default()
    })
    .expect("known method");
    w.add_force(Gravity::EARTH);
    w.add_force(LinearDrag { rate: 0.1 });
    w.add_collider(Plane::floor(
        0.0,
        Material {
            restitution: 0.6,
            friction: 0.2,
        },
    ));
    w.add_emitter(Emitter {
        rate: 3000.0,
        lifetime: 1.5,
        ..Emitter::default()
    })
    .expect("valid emitter");
    let player = w.spawn(Particle {
        position: Vec3::new(0.0, 1.0, 0.0),
        radius: 0.2,
        ..Particle::default()
    });
    (w, player.expect("spawn"))
}

/// Kicks the player for each key pressed this tick.
fn apply(world: &mut World, player: Entity, input: &TickInput) {
    for key in input.pressed.iter() {
        let v = world.velocity(player).expect("alive");
        let kick = match key {
            Key::Left => Vec3::new(-1.0, 0.0, 0.0),
            Key::Right => Vec3::new(1.0, 0.0, 0.0),
            _ => Vec3::new(0.0, 4.0, 0.0),
        };
        world.set_velocity(player, v + kick).expect("finite");
    }
}

/// The clock's present: simulated time plus backlog.
fn present(clock: &FixedClock) -> f64 {
    clock.time() + clock.backlog()
}

fn tap(queue: &mut InputQueue, key: Key, at: f64) {
    queue.push(InputEvent::Key { key, down: true }, at);
    queue.push(InputEvent::Key { key, down: false }, at + 0.05);
}

/// Plays 4 seconds live: keys tapped at given frames; returns the recording,
/// the final hash and the number of taps.
fn play_live(source: &mut dyn TimeSource, threshold: usize) -> (Recording, u64, usize) {
    let (mut world, player) = scene(threshold);
    let mut clock = FixedClock::default();
    let mut queue = InputQueue::default();
    let mut recording = Recording {
        game: "replay".into(),
        hz: 60.0,
        seed: 7,
        integrator: None,
        ticks: 240,
        inputs: Vec::new(),
        controls: Vec::new(),
        other_players: Vec::new(),
        checksum: None,
    };
    let (mut frame_index, mut taps, mut seen) = (0u64, 0, 0);
    let mut carried = TickInput::default();
    while clock.tick() < 240 {
        // Keys tapped during this frame (by frame count, as a player would).
        match frame_index % 37 {
            3 => tap(&mut queue, Key::Space, 0.3),
            11 => tap(&mut queue, Key::Left, 0.5),
            19 => tap(&mut queue, Key::Right, 0.1),
            _ => {}
        }
        taps += usize::from(matches!(frame_index % 37, 3 | 11 | 19));
        frame_index += 1;
        let from = present(&clock);
        let frame = clock.advance(source.next_frame()).expect("frame");
        queue.stamp(from, present(&clock));
        for step in frame.fixed_steps() {
            if step.tick >= 240 {
                break;
            }
            let input = queue.tick(step.time + step.dt);
            seen += input.pressed.iter().count();
            if input != carried {
                recording.inputs.push((step.tick, input));
            }
            carried = input.carried();
            world.step_with(step, |w, _| apply(w, player, &input)).expect("step");
        }
    }
    assert_eq!(world.tick(), 240);
    // Every tap was seen by exactly one step, or still waits.
    queue.stamp(present(&clock), present(&clock));
    seen += queue.tick(f64::INFINITY).pressed.iter().count();
    assert_eq!(seen, taps);
    (recording, world.state_hash(), taps)
}

fn replay(recording: &Recording, source: &mut dyn TimeSource, threshold: usize) -> u64 {
    let (mut world, player) = scene(threshold);
    let mut clock = FixedClock::default();
    let mut inputs = recording.inputs.iter().peekable();
    let mut input = TickInput::default();
    while clock.tick() < 240 {
        let frame = clock.advance(source.next_frame()).expect("frame");
        for step in frame.fixed_steps() {
            if step.tick >= 240 {
                break;
            }
            input = match inputs.next_if(|(tick, _)| *tick == step.tick) {
                Some((_, recorded)) => *recorded,
                None => input.carried(),
            };
            world.step_with(step, |w, _| apply(w, player, &input)).expect("step");
        }
    }
    world.state_hash()
}

#[test]
fn replays_are_bit_identical_across_frame_timing_and_threads() {
    let (recording, live, taps) = play_live(&mut JitteryCadence::new(1.0 / 50.0, 42), usize::MAX);
    assert!(taps > 10, "the run saw input: {taps} taps");
    // Same inputs, a 144 Hz display, serial.
    assert_eq!(replay(&recording, &mut FixedCadence::hz(144.0), usize::MAX), live);
    // Same inputs, jittery 30 Hz display, fused step split over 1 and 2 threads.
    for threads in [1, 2] {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .expect("pool");
        let hash = pool.install(|| replay(&recording, &mut JitteryCadence::new(1.0 / 30.0, 9), 512));
        assert_eq!(hash, live, "{threads} threads");
    }
    // A different input changes the outcome (the hash is not blind).
    let mut other = recording.clone();
    other.inputs[0].1.pressed = vec![Key::Left].into();
    assert_ne!(replay(&other, &mut FixedCadence::hz(60.0), usize::MAX), live);
}

/// Frame durations of a display: steady at `hz`, or jittering about it.
fn frames(source: &mut dyn TimeSource, seconds: f64) -> Vec<f64> {
    let mut total = 0.0;
    let mut out = Vec::new();
    while total < seconds {
        let frame = source.next_frame();
        total += frame;
        out.push(frame);
    }
    out
}

/// The ticks that see presses made at real times `presses` (seconds),
/// each handed over with where in its frame it arrived.
fn ticks_seeing(presses: &[f64], frame_times: &[f64]) -> Vec<u64> {
    let mut clock = FixedClock::default();
    let mut queue = InputQueue::default();
    let (mut start, mut seen) = (0.0, Vec::new());
    for &duration in frame_times {
        for &at in presses.iter().filter(|&&t| t >= start && t < start + duration) {
            queue.push(
                InputEvent::Key {
                    key: Key::Space,
                    down: true,
                },
                (at - start) / duration,
            );
            queue.push(
                InputEvent::Key {
                    key: Key::Space,
                    down: false,
                },
                (at - start) / duration,
            );
        }
        start += duration;
        let from = present(&clock);
        let frame = clock.advance(duration).expect("frame");
        queue.stamp(from, present(&clock));
        for step in frame.fixed_steps() {
            if queue.tick(step.time + step.dt).pressed(Key::Space) {
                seen.push(step.tick);
            }
        }
    }
    seen
}

#[test]
fn a_press_reaches_the_tick_of_its_time_whatever_the_frame_timing() {
    // Presses a third of the way into ticks 5, 31, 32, 100 and 177 (60 Hz).
    let ticks = [5u64, 31, 32, 100, 177];
    let presses: Vec<f64> = ticks.iter().map(|&k| (k as f64 + 0.33) / 60.0).collect();
    let displays: [(&str, Box<dyn TimeSource>); 5] = [
        ("240 Hz", Box::new(FixedCadence::hz(240.0))),
        ("144 Hz", Box::new(FixedCadence::hz(144.0))),
        ("60 Hz", Box::new(FixedCadence::hz(60.0))),
        ("20 Hz", Box::new(FixedCadence::hz(20.0))),
        ("jittery 45 Hz", Box::new(JitteryCadence::new(1.0 / 45.0, 3))),
    ];
    for (name, mut display) in displays {
        let frame_times = frames(display.as_mut(), 3.1);
        // Each press is seen once, by the tick whose time window holds it:
        // at 20 Hz a frame runs three steps, and the press goes to the one
        // it happened in, not to the frame's first.
        assert_eq!(ticks_seeing(&presses, &frame_times), ticks, "{name}");
    }
}

#[test]
fn recordings_round_trip_and_are_not_overwritten() {
    let (recording, _, _) = play_live(&mut FixedCadence::hz(60.0), usize::MAX);
    let dir = std::env::temp_dir().join(format!("tickwork-replay-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    let path = dir.join("run.ron");
    let _ = std::fs::remove_file(&path);
    recording.save(&path, false).expect("write");
    let err = recording.save(&path, false).expect_err("exists");
    assert!(
        err.to_string()
            .ends_with("run.ron: exists; pass --force to overwrite it"),
        "{err}"
    );
    let back = Recording::load(&path).expect("read");
    assert_eq!(back, recording);
    std::fs::write(
        &path,
        "Recording(game: \"replay\", hz: 60.0, seed: 7, integrator: None, ticks: 240, inputs: [(3, TickInput(held: [Sideways]))])",
    )
    .expect("write");
    let err = Recording::load(&path).expect_err("bad variant");
    assert!(
        err.to_string().contains("line 1, column ") && err.to_string().contains("`Sideways`"),
        "{err}"
    );
    std::fs::remove_dir_all(&dir).expect("clean up");
}

#[test]
fn fused_parallel_and_plain_steps_agree_bit_for_bit() {
    // The same pointwise scene stepped by the fused path (split over lanes)
    // and by the plain whole-slice path (forced by a non-pointwise no-op
    // collider) must agree exactly.
    let run = |plain: bool| {
        let (mut w, _) = scene(1000);
        if plain {
            w.add_collider(support::ForcePlainPath);
        }
        let mut fused_lanes = 0;
        for tick in 0..120 {
            let report = w.step(tickwork_engine::FixedStep {
                tick,
                time: tick as f64 / 60.0,
                dt: 1.0 / 60.0,
            });
            fused_lanes = fused_lanes.max(report.expect("step").fused_lanes);
        }
        (support::hash_without_plain_path(&mut w), fused_lanes)
    };
    let pool = rayon::ThreadPoolBuilder::new().num_threads(2).build().expect("pool");
    let (fused, lanes) = pool.install(|| run(false));
    let (plain, plain_lanes) = run(true);
    assert_eq!(lanes, 2, "the fused path ran on two lanes");
    assert_eq!(plain_lanes, 0);
    assert_eq!(fused, plain);
}
