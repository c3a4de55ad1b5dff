//! Determinism: recorded per-tick inputs replay to a bit-identical state,
//! whatever the frame timing and the number of threads, and the fused,
//! parallel step equals the plain one.

mod support;
use glam::Vec3;
use tickwork_engine::clock::{FixedCadence, JitteryCadence, TimeSource};
use tickwork_engine::{
    Emitter, Entity, FixedClock, Gravity, InputLog, InputQueue, LinearDrag, Material, Particle, Plane, World,
    WorldConfig,
};

/// What the player can do.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
enum Key {
    Left,
    Right,
    Jump,
}

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

fn apply(world: &mut World, player: Entity, keys: &[Key]) {
    for key in keys {
        let v = world.velocity(player).expect("alive");
        let kick = match key {
            Key::Left => Vec3::new(-1.0, 0.0, 0.0),
            Key::Right => Vec3::new(1.0, 0.0, 0.0),
            Key::Jump => Vec3::new(0.0, 4.0, 0.0),
        };
        world.set_velocity(player, v + kick).expect("finite");
    }
}

/// Plays 4 seconds live: keys arrive at given frames; returns the log and the final hash.
fn play_live(source: &mut dyn TimeSource, threshold: usize) -> (InputLog<Key>, u64, usize) {
    let (mut world, player) = scene(threshold);
    let mut clock = FixedClock::default();
    let mut queue = InputQueue::default();
    let mut log = InputLog::default();
    let mut frame_index = 0u64;
    let mut pushed = 0;
    while clock.tick() < 240 {
        // Keys pressed during this frame (by frame count, as a player would).
        match frame_index % 37 {
            3 => queue.push(Key::Jump),
            11 => queue.push(Key::Left),
            19 => {
                queue.push(Key::Right);
                queue.push(Key::Right);
            }
            _ => {}
        }
        pushed = queue.pending().len() + log.events.len();
        frame_index += 1;
        let frame = clock.advance(source.next_frame()).expect("frame");
        for step in frame.fixed_steps() {
            if step.tick >= 240 {
                break;
            }
            let keys = queue.begin_step().to_vec();
            log.record(step.tick, &keys);
            world.step_with(step, |w, _| apply(w, player, &keys)).expect("step");
        }
    }
    assert_eq!(world.tick(), 240);
    // Every key pressed was seen by exactly one step, or still waits.
    assert_eq!(log.events.len() + queue.pending().len(), pushed);
    (log, world.state_hash(), pushed)
}

fn replay(log: &InputLog<Key>, source: &mut dyn TimeSource, threshold: usize) -> u64 {
    let (mut world, player) = scene(threshold);
    let mut log = log.clone();
    let mut clock = FixedClock::default();
    while clock.tick() < 240 {
        let frame = clock.advance(source.next_frame()).expect("frame");
        for step in frame.fixed_steps() {
            if step.tick >= 240 {
                break;
            }
            let keys: Vec<Key> = log.events_at(step.tick).iter().map(|(_, k)| *k).collect();
            world.step_with(step, |w, _| apply(w, player, &keys)).expect("step");
        }
    }
    world.state_hash()
}

#[test]
fn replays_are_bit_identical_across_frame_timing_and_threads() {
    let (log, live, pushed) = play_live(&mut JitteryCadence::new(1.0 / 50.0, 42), usize::MAX);
    assert!(
        log.events.len() > 10 && pushed >= log.events.len(),
        "the run saw input: {}",
        log.events.len()
    );
    // Same inputs, a 144 Hz display, serial.
    assert_eq!(replay(&log, &mut FixedCadence::hz(144.0), usize::MAX), live);
    // Same inputs, jittery 30 Hz display, fused step split over 1 and 2 threads.
    for threads in [1, 2] {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .expect("pool");
        let hash = pool.install(|| replay(&log, &mut JitteryCadence::new(1.0 / 30.0, 9), 512));
        assert_eq!(hash, live, "{threads} threads");
    }
    // A different input changes the outcome (the hash is not blind).
    let mut other = log.clone();
    other.events[0].1 = Key::Left;
    assert_ne!(replay(&other, &mut FixedCadence::hz(60.0), usize::MAX), live);
}

#[test]
fn key_presses_are_never_lost_or_doubled_across_frames() {
    // A 240 Hz display at 60 Hz steps runs zero steps in most frames; a 20 Hz
    // display runs three per frame. Either way each press reaches one step.
    for display_hz in [240.0, 20.0] {
        let mut clock = FixedClock::default();
        let mut queue = InputQueue::default();
        let mut seen = Vec::new();
        let mut source = FixedCadence::hz(display_hz);
        for frame_index in 0..200u32 {
            if frame_index % 5 == 0 {
                queue.push(frame_index);
            }
            let frame = clock.advance(source.next_frame()).expect("frame");
            for _ in frame.fixed_steps() {
                seen.extend_from_slice(queue.begin_step());
            }
        }
        seen.extend_from_slice(queue.begin_step());
        let pushed: Vec<u32> = (0..200).filter(|f| f % 5 == 0).collect();
        assert_eq!(seen, pushed, "display at {display_hz} Hz");
    }
}

#[test]
fn log_files_round_trip_and_are_not_overwritten() {
    let (log, _, _) = play_live(&mut FixedCadence::hz(60.0), usize::MAX);
    let dir = std::env::temp_dir().join(format!("tickwork-replay-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    let path = dir.join("run.ron");
    let _ = std::fs::remove_file(&path);
    log.save(&path, false).expect("write");
    let err = log.save(&path, false).expect_err("exists");
    assert!(
        err.to_string()
            .ends_with("exists; not overwriting a recording without being asked"),
        "{err}"
    );
    let back: InputLog<Key> = InputLog::load(&path).expect("read");
    assert_eq!(back.events, log.events);
    std::fs::write(&path, "(events: [(3, Jump), (4, Sideways)])").expect("write");
    let err = InputLog::<Key>::load(&path).expect_err("bad variant");
    assert!(
        err.to_string()
            .contains("line 1, column 26: Unexpected variant named `Sideways`"),
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
            fused_lanes = fused_lanes.max(report.expect("step").lanes);
        }
        (w.state_hash(), fused_lanes)
    };
    let pool = rayon::ThreadPoolBuilder::new().num_threads(2).build().expect("pool");
    let (fused, lanes) = pool.install(|| run(false));
    let (plain, plain_lanes) = run(true);
    assert_eq!(lanes, 2, "the fused path ran on two lanes");
    assert_eq!(plain_lanes, 0);
    assert_eq!(fused, plain);
}
