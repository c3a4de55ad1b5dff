//! A hostile user's table: every subcommand of `tickwork` and every demo,
//! given bad values. Each case must fail with exit code 1 or 2, without a
//! panic, with a message naming the option and the value (or the limit),
//! and without touching the sentinel files where output would go or
//! creating the directory frames would go to.

use std::path::{Path, PathBuf};
use std::process::Command;

const SENTINEL: &str = "sentinel: must stay as it is\n";

/// Where one table's files live: sentinel files, an empty directory, and
/// a directory that must never be created.
struct Sandbox {
    root: PathBuf,
}

impl Sandbox {
    fn new(name: &str) -> Self {
        let sandbox = Self {
            root: Path::new(env!("CARGO_MANIFEST_DIR"))
                .join("../target/test-demos/hostile")
                .join(name),
        };
        sandbox.reset();
        sandbox
    }

    /// Lays the sandbox out afresh (after a case damaged it, the table goes on).
    fn reset(&self) {
        let _ = std::fs::remove_dir_all(&self.root);
        std::fs::create_dir_all(self.root.join("empty")).expect("a scratch directory");
        for file in Self::SENTINELS {
            std::fs::write(self.root.join(file), SENTINEL).expect("a sentinel file");
        }
    }

    const SENTINELS: [&str; 4] = ["sentinel.gif", "sentinel.ron", "sentinel.csv", "sentinel-file"];

    /// `{gif}`, `{ron}`, `{csv}`, `{file}` (sentinels), `{dir}` (an empty
    /// directory), `{out}` (must not appear), `{missing}` (a directory that
    /// does not exist), `{scene}` (a shipped scene).
    fn expand(&self, arg: &str) -> String {
        let path = |name: &str| self.root.join(name).display().to_string();
        arg.replace("{gif}", &path("sentinel.gif"))
            .replace("{ron}", &path("sentinel.ron"))
            .replace("{csv}", &path("sentinel.csv"))
            .replace("{file}", &path("sentinel-file"))
            .replace("{dir}", &path("empty"))
            .replace("{out}", &path("out"))
            .replace("{missing}", &path("missing"))
            .replace(
                "{scene}",
                &Path::new(env!("CARGO_MANIFEST_DIR"))
                    .join("../assets/scenes/projectile.ron")
                    .display()
                    .to_string(),
            )
    }

    /// What is wrong with the sandbox after a case, if anything.
    fn damage(&self) -> Option<String> {
        for file in Self::SENTINELS {
            let text = std::fs::read_to_string(self.root.join(file)).unwrap_or_default();
            if text != SENTINEL {
                return Some(format!("{file} was changed or removed"));
            }
        }
        if self.root.join("out").exists() {
            return Some("the output directory was created".into());
        }
        if self.root.join("missing").exists() {
            return Some("the missing directory was created".into());
        }
        let entries = std::fs::read_dir(self.root.join("empty")).map_or(usize::MAX, Iterator::count);
        (entries != 0).then(|| "something was written into the empty directory".into())
    }
}

/// Runs each case (`args`, the texts the error must contain) of `program`
/// with `base` arguments added unless the case gives that option itself;
/// returns every failure, so one run shows them all.
fn run_table(program: &str, sandbox: &Sandbox, base: &[&str], cases: &[(&[&str], &[&str])]) -> Vec<String> {
    let mut failures = Vec::new();
    for &(args, expected) in cases {
        let mut argv: Vec<String> = args.iter().map(|a| sandbox.expand(a)).collect();
        let mut k = 0;
        while k < base.len() {
            let option = base[k];
            let takes_value = base.get(k + 1).is_some_and(|v| !v.starts_with("--"));
            if !args.contains(&option) {
                argv.push(sandbox.expand(option));
                if takes_value {
                    argv.push(sandbox.expand(base[k + 1]));
                }
            }
            k += if takes_value { 2 } else { 1 };
        }
        let output = Command::new(program)
            .args(&argv)
            // No window is opened, whatever the test machine has.
            .env_remove("DISPLAY")
            .env_remove("WAYLAND_DISPLAY")
            .output()
            .expect("the program runs");
        let stderr = String::from_utf8_lossy(&output.stderr);
        let name = Path::new(program)
            .file_name()
            .map_or_else(String::new, |n| n.to_string_lossy().into());
        let case = format!("{name} {}", argv.join(" "));
        if !matches!(output.status.code(), Some(1 | 2)) {
            failures.push(format!("{case}: exit {:?}, expected 1 or 2\n{stderr}", output.status));
        }
        if stderr.contains("panicked at") {
            failures.push(format!("{case}: panicked\n{stderr}"));
        }
        let expected: Vec<String> = expected.iter().map(|e| sandbox.expand(e)).collect();
        if let Some(missing) = expected.iter().find(|e| !stderr.contains(e.as_str())) {
            failures.push(format!("{case}: expected {missing:?} in\n{stderr}"));
        }
        if let Some(damage) = sandbox.damage() {
            failures.push(format!("{case}: {damage}"));
            sandbox.reset();
        }
    }
    failures
}

/// The cases every game shares (they all parse `RunOptions`).
const GAME_CASES: &[(&[&str], &[&str])] = &[
    (&["--hz", "-1"], &["--hz", "-1"]),
    (&["--hz", "0"], &["--hz", "'0'"]),
    (&["--hz", "NaN"], &["--hz", "NaN"]),
    (&["--hz", "1e7"], &["invalid rate in Hz: 1e7 (accepted: from 1/3600"]),
    (
        &["--time-scale", "1e30"],
        &["time_scale: 1e30 (expected from 1e-6 to 1e6"],
    ),
    (&["--time-scale", "-1"], &["--time-scale", "-1"]),
    (&["--frames", "-1"], &["--frames", "-1"]),
    (
        &["--frames", "100000000"],
        &["--frames 100000000 is past the limit of 1000000 off-screen frames (MAX_OFFSCREEN_FRAMES)"],
    ),
    (&["--size", "0x100"], &["--size", "0x100"]),
    (&["--size", "-5x5"], &["--size", "-5x5"]),
    (&["--size", "16385x16"], &["16385x16"]),
    (&["--seed", "-1"], &["--seed", "-1"]),
    (&["--integrator", "eulr"], &["unknown integrator 'eulr'"]),
    (&["--display-hz", "-60"], &["--display-hz", "-60", "accepted range"]),
    (&["--display-hz", "1e300"], &["--display-hz", "1e300", "accepted range"]),
    (&["--hold", "NaN"], &["--hold", "NaN"]),
    (&["--gif", "{gif}"], &["{gif}: exists; pass --force"]),
    (&["--gif", "{dir}"], &["{dir}: is a directory"]),
    (&["--out", "{file}"], &["{file}: is a file"]),
    (&["--record", "{ron}"], &["{ron}: exists; pass --force"]),
    (
        &["--record", "{missing}/r.ron"],
        &["the directory {missing} does not exist"],
    ),
    (
        &["--replay", "/dev/zero"],
        &["/dev/zero: it is larger than the limit", "Recording::MAX_FILE_BYTES"],
    ),
    (&["--replay", "{file}"], &["{file}: line 1, column 1"]),
    (&["--replay", "{missing}/r.ron"], &["{missing}/r.ron"]),
    (&["--bogus"], &["unexpected argument '--bogus'"]),
    (
        &["--sync-test", "0"],
        &["--sync-test 0: the check distance must be 1 to 7 ticks"],
    ),
    (&["--sync-test", "-2"], &["--sync-test", "-2"]),
    (
        &["--sync-test", "3", "--record", "{missing}/r.ron"],
        &["--sync-test", "--record", "cannot be used with"],
    ),
];

#[test]
fn every_demo_refuses_bad_options_and_files_without_touching_its_outputs() {
    let mut failures = Vec::new();
    for (name, program) in [
        ("orbits", env!("CARGO_BIN_EXE_orbits")),
        ("fountain", env!("CARGO_BIN_EXE_fountain")),
        ("cloth", env!("CARGO_BIN_EXE_cloth")),
        ("tops", env!("CARGO_BIN_EXE_tops")),
        ("lander", env!("CARGO_BIN_EXE_lander")),
        ("breakout", env!("CARGO_BIN_EXE_breakout")),
    ] {
        let sandbox = Sandbox::new(name);
        // Off-screen, into `{out}`: a case wrongly accepted leaves frames there.
        let base = ["--headless", "--frames", "2", "--out", "{out}"];
        failures.extend(run_table(program, &sandbox, &base, GAME_CASES));
    }
    // The tops fix every world's integrator: a name would go unused.
    let sandbox = Sandbox::new("tops-integrator");
    let base = ["--headless", "--frames", "2", "--out", "{out}"];
    let tops: &[(&[&str], &[&str])] = &[(
        &["--integrator", "rk4"],
        &[
            "--integrator rk4: tops fixes the integrator of each of its worlds",
            "run it without --integrator",
        ],
    )];
    failures.extend(run_table(env!("CARGO_BIN_EXE_tops"), &sandbox, &base, tops));
    assert!(
        failures.is_empty(),
        "{} failures:\n{}",
        failures.len(),
        failures.join("\n\n")
    );
}

#[test]
fn every_subcommand_refuses_bad_options_and_files_without_touching_its_outputs() {
    let tickwork = env!("CARGO_BIN_EXE_tickwork");
    let sim: &[(&[&str], &[&str])] = &[
        (&["sim", "{scene}", "--steps", "-1"], &["--steps", "-1"]),
        (
            &["sim", "{scene}", "--steps", "100000000000"],
            &["--steps: 100000000000 steps, past the limit of 10000000000 steps a run"],
        ),
        (
            &["sim", "{scene}", "--until", "1e300"],
            &["--until: 1e300 s is 6e301 steps at 60 Hz, past the limit"],
        ),
        (&["sim", "{scene}", "--until", "NaN"], &["--until: NaN"]),
        (&["sim", "{scene}", "--until", "-inf"], &["--until", "-inf"]),
        (&["sim", "{scene}", "--hz", "-1"], &["--hz", "-1"]),
        (
            &["sim", "{scene}", "--hz", "5e-7"],
            &["--hz 5e-7: ", "invalid rate in Hz: 5e-7 (accepted: from 1/3600"],
        ),
        (
            &["sim", "{scene}", "--hz", "1e7"],
            &["--hz 1e7: ", "invalid rate in Hz: 1e7 (accepted"],
        ),
        (
            &["sim", "{scene}", "--dt", "3601"],
            &["--dt 3601: ", "invalid step in seconds: 3601 (accepted"],
        ),
        (
            &["sim", "{scene}", "--dt", "1e-7"],
            &["--dt 1e-7: ", "invalid step in seconds: 1e-7 (accepted"],
        ),
        (&["sim", "{scene}", "--every", "0"], &["--every: must be at least 1"]),
        (&["sim", "{scene}", "--every", "-1"], &["--every", "-1"]),
        (
            &["sim", "{scene}", "--trace", "{csv}"],
            &["{csv}: exists; pass --force"],
        ),
        (
            &["sim", "{scene}", "--trace", "{dir}"],
            &["--trace: {dir} is a directory"],
        ),
        (
            &["sim", "{scene}", "--trace", "{missing}/t.csv"],
            &["--trace: {missing}/t.csv: the directory {missing} does not exist"],
        ),
        (
            &["sim", "{scene}", "--integrator", "eulr"],
            &["unknown integrator 'eulr'"],
        ),
        (
            &["sim", "/dev/zero"],
            &["/dev/zero: cannot read the scene: it is larger than the limit"],
        ),
        (&["sim", "{missing}/s.ron"], &["{missing}/s.ron: cannot read the scene"]),
        (&["sim", "{dir}"], &["{dir}: cannot read the scene"]),
        (&["sim", "{file}"], &["{file}:1:1: Expected struct `SceneFile`"]),
    ];
    let render: &[(&[&str], &[&str])] = &[
        (&["render", "{scene}", "--frames", "-1"], &["--frames", "-1"]),
        (
            &["render", "{scene}", "--frames", "0", "--gif", "{out}/z.gif"],
            &["--frames: 0 frames; pass at least 1"],
        ),
        (
            &["render", "{scene}", "--frames", "100000000"],
            &["--frames 100000000 is past the limit of 1000000 off-screen frames"],
        ),
        (&["render", "{scene}", "--size", "-5x5"], &["--size", "-5x5"]),
        (&["render", "{scene}", "--size", "0x0"], &["--size", "0x0"]),
        (&["render", "{scene}", "--size", "16385x16"], &["16385x16"]),
        (
            &["render", "{scene}", "--display-hz", "-60"],
            &["--display-hz", "-60", "accepted range"],
        ),
        (
            &["render", "{scene}", "--display-hz", "1e300"],
            &["--display-hz", "1e300", "accepted range"],
        ),
        (
            &["render", "{scene}", "--display-hz", "1e-300"],
            &["--display-hz", "1e-300", "accepted range"],
        ),
        (
            &["render", "{scene}", "--gif", "{gif}"],
            &["{gif}: exists; pass --force"],
        ),
        (
            &["render", "{scene}", "--gif", "{dir}"],
            &["--gif: {dir} is a directory"],
        ),
        (&["render", "{scene}", "--out", "{file}"], &["{file}: is a file"]),
        (&["render", "{scene}", "--blend", "bogus"], &["--blend", "bogus"]),
        (
            &["render", "{scene}", "--interpolation", "bogus"],
            &["--interpolation", "bogus"],
        ),
        (&["render", "{scene}", "--jitter-seed", "-1"], &["--jitter-seed", "-1"]),
        (
            &["render", "{scene}", "--integrator", "eulr"],
            &["unknown integrator 'eulr'"],
        ),
        (
            &["render", "/dev/zero"],
            &["/dev/zero: cannot read the scene: it is larger than the limit"],
        ),
    ];
    let view: &[(&[&str], &[&str])] = &[
        (&["view", "{scene}", "--hold", "NaN"], &["--hold", "NaN"]),
        (&["view", "{scene}", "--hold", "-1"], &["--hold", "-1"]),
        (&["view", "{scene}", "--frames", "-1"], &["--frames", "-1"]),
        (&["view", "{scene}", "--size", "0x0"], &["--size", "0x0"]),
        (
            &["view", "{scene}", "--display-hz", "0"],
            &["--display-hz", "accepted range"],
        ),
        (
            &["view", "{scene}", "--integrator", "eulr"],
            &["unknown integrator 'eulr'"],
        ),
        (&["view", "/dev/zero"], &["/dev/zero: cannot read the scene"]),
    ];
    let lab: &[(&[&str], &[&str])] = &[
        (
            &["lab", "convergence", "--problem", "bogus"],
            &["unknown problem 'bogus'"],
        ),
        (&["lab", "bogus"], &["invalid value 'bogus' for '<STUDY>'"]),
        (&["lab", "convergence", "--out", "{file}"], &["--out: {file} is a file"]),
    ];
    let others: &[(&[&str], &[&str])] = &[
        (&["integrators", "--bogus"], &["unexpected argument '--bogus'"]),
        (&["bogus"], &["unrecognized subcommand 'bogus'"]),
    ];
    let mut failures = Vec::new();
    let sandbox = Sandbox::new("tickwork");
    failures.extend(run_table(tickwork, &sandbox, &[], sim));
    failures.extend(run_table(
        tickwork,
        &sandbox,
        &["--frames", "2", "--out", "{out}"],
        render,
    ));
    failures.extend(run_table(tickwork, &sandbox, &["--frames", "2"], view));
    failures.extend(run_table(tickwork, &sandbox, &["--out", "{out}"], lab));
    failures.extend(run_table(tickwork, &sandbox, &[], others));
    assert!(
        failures.is_empty(),
        "{} failures:\n{}",
        failures.len(),
        failures.join("\n\n")
    );
}

#[test]
fn a_size_within_the_device_limit_but_past_its_memory_is_an_error_not_a_panic() {
    // 16384 x 16384 is within a software adapter's texture limit, but with
    // MSAA its buffers need gigabytes: wgpu's uncaptured-error handler
    // panicked. Either the frame is drawn, or the error says what ran out.
    let sandbox = Sandbox::new("huge");
    let out = sandbox.expand("{out}");
    let output = Command::new(env!("CARGO_BIN_EXE_tickwork"))
        .args([
            "render",
            &sandbox.expand("{scene}"),
            "--frames",
            "1",
            "--size",
            "16384x16384",
            "--out",
            &out,
        ])
        .output()
        .expect("runs");
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(!stderr.contains("panicked at"), "{stderr}");
    if output.status.success() {
        let frame = Path::new(&out).join("frame_00000.png");
        assert_eq!(image::image_dimensions(&frame).expect("a frame"), (16384, 16384));
    } else {
        assert_eq!(output.status.code(), Some(1), "{stderr}");
        assert!(
            stderr.contains("out of GPU memory for 16384x16384 frame buffers with 4 samples per pixel"),
            "{stderr}"
        );
        assert!(!Path::new(&out).exists(), "nothing written");
    }
}
