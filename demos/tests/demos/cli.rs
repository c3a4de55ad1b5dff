//! The `tickwork` binary as a user runs it.
// Reference values and set-ups computed natively (never in a page): the
// platform's own functions are fine here (clippy.toml bans them in the engine).
#![allow(clippy::disallowed_methods)]

use std::process::Command;

fn tickwork(args: &[&str]) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_tickwork"))
        .args(args)
        .output()
        .expect("runs")
}

#[test]
fn integrators_json_lists_every_registered_method_with_its_fields() {
    let output = tickwork(&["integrators", "--json"]);
    assert!(output.status.success(), "{}", String::from_utf8_lossy(&output.stderr));
    let methods: Vec<serde_json::Value> = serde_json::from_slice(&output.stdout).expect("a JSON array");
    assert_eq!(methods.len(), tickwork_integrators::METHODS.len());
    for (json, info) in methods.iter().zip(tickwork_integrators::METHODS) {
        assert_eq!(json["name"], info.name);
        assert_eq!(json["order"], info.order);
        assert_eq!(json["order_velocity_forces"], info.order_velocity_forces);
        assert_eq!(json["evaluations"], info.evaluations);
        assert_eq!(json["symplectic"], info.symplectic);
        assert_eq!(json["reversible"], info.reversible);
        assert_eq!(json["self_starting"], info.self_starting);
        assert_eq!(json["aliases"].as_array().map(Vec::len), Some(info.aliases.len()));
    }
    let rk4 = methods.iter().find(|m| m["name"] == "rk4").expect("rk4");
    assert_eq!((rk4["order"].as_u64(), rk4["evaluations"].as_u64()), (Some(4), Some(4)));
    let leapfrog = methods.iter().find(|m| m["name"] == "leapfrog").expect("leapfrog");
    assert_eq!(leapfrog["order_velocity_forces"].as_u64(), Some(1));
    assert_eq!(leapfrog["symplectic"], true);
}

#[test]
fn integrators_table_has_a_row_per_method_and_the_angular_methods() {
    let output = tickwork(&["integrators"]);
    assert!(output.status.success());
    let text = String::from_utf8(output.stdout).expect("utf-8");
    let mut lines = text.lines();
    assert!(
        lines
            .next()
            .is_some_and(|header| header.starts_with("name") && header.contains("order x/v/drag"))
    );
    for info in tickwork_integrators::METHODS {
        assert!(
            text.lines().any(|l| l.starts_with(&format!("{} ", info.name))),
            "no row for {}",
            info.name
        );
    }
    let verlet: Vec<&str> = text
        .lines()
        .find(|l| l.starts_with("position_verlet "))
        .expect("row")
        .split_whitespace()
        .collect();
    assert_eq!(
        &verlet[..3],
        ["position_verlet", "2/1/1", "1"],
        "orders and evaluations"
    );
    assert!(text.contains("exponential_map"), "{text}");
    // No subcommand is the same listing.
    assert_eq!(tickwork(&[]).stdout, text.as_bytes());
}

#[test]
fn an_unknown_subcommand_is_an_error_naming_it() {
    let output = tickwork(&["integrater"]);
    assert!(!output.status.success());
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(stderr.contains("unrecognized subcommand 'integrater'"), "{stderr}");
    assert!(stderr.contains("integrators"), "suggests the right one: {stderr}");
}

fn scene(name: &str) -> String {
    format!("{}/../assets/scenes/{name}", env!("CARGO_MANIFEST_DIR"))
}

fn temp_path(name: &str) -> std::path::PathBuf {
    let dir = std::env::temp_dir().join(format!("tickwork-cli-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    let path = dir.join(name);
    let _ = std::fs::remove_file(&path);
    path
}

#[test]
fn sim_trace_of_the_projectile_matches_the_closed_form() {
    let trace = temp_path("projectile.csv");
    let output = tickwork(&[
        "sim",
        &scene("projectile.ron"),
        "--trace",
        trace.to_str().expect("utf-8"),
        "--every",
        "10",
    ]);
    assert!(output.status.success(), "{}", String::from_utf8_lossy(&output.stderr));
    let summary = String::from_utf8(output.stdout).expect("utf-8");
    assert!(summary.contains("steps       150 (t = 2.500000 s)"), "{summary}");
    assert!(summary.contains("integrator  velocity_verlet"), "{summary}");
    let text = std::fs::read_to_string(&trace).expect("trace written");
    let mut lines = text.lines();
    assert_eq!(
        lines.next(),
        Some("step,t,entity,generation,x,y,z,vx,vy,vz,qx,qy,qz,qw,wx,wy,wz")
    );
    let (v0, g) = ([7.5f64, 12.990381, 0.0], -9.81f64);
    let mut rows = 0;
    for line in lines {
        let f: Vec<&str> = line.split(',').collect();
        let num = |i: usize| f[i].parse::<f64>().expect("number");
        let t = num(1);
        assert_eq!(num(0) as u64 % 10, 0);
        assert!((num(4) - v0[0] * t).abs() < 1e-4, "{line}");
        assert!((num(5) - (v0[1] * t + 0.5 * g * t * t)).abs() < 2e-4, "{line}");
        assert!((num(8) - (v0[1] + g * t)).abs() < 1e-4, "{line}");
        rows += 1;
    }
    assert_eq!(rows, 16, "the initial state and every 10th of 150 steps");
    // The trace is not overwritten without --force.
    let again = tickwork(&[
        "sim",
        &scene("projectile.ron"),
        "--trace",
        trace.to_str().expect("utf-8"),
    ]);
    assert!(!again.status.success());
    let message = String::from_utf8_lossy(&again.stderr);
    assert!(message.ends_with("exists; pass --force to overwrite it\n"), "{message}");
}

#[test]
fn sim_reports_energy_drift_by_integrator() {
    let drift = |method: &str| {
        let output = tickwork(&[
            "sim",
            &scene("kepler.ron"),
            "--integrator",
            method,
            "--until",
            "31.4159",
        ]);
        assert!(output.status.success(), "{}", String::from_utf8_lossy(&output.stderr));
        let text = String::from_utf8(output.stdout).expect("utf-8");
        let line = text
            .lines()
            .find(|l| l.starts_with("energy"))
            .expect("energy line")
            .to_owned();
        let value = line
            .rsplit("drift ")
            .next()
            .expect("drift")
            .trim_end_matches(')')
            .to_owned();
        value.parse::<f64>().unwrap_or_else(|_| panic!("{line}"))
    };
    assert!(drift("velocity_verlet").abs() < 1e-4);
    assert!(
        drift("explicit_euler") > 0.3,
        "explicit Euler gains energy and spirals out"
    );
}

#[test]
fn sim_errors_say_what_was_wrong() {
    // The first line says what the command was doing; a `caused by` line
    // gives the engine's details.
    let cases: [(&[&str], &str); 5] = [
        (
            &["sim", "no/such.ron"],
            "tickwork: cannot load the scene no/such.ron\n  caused by: no/such.ron: cannot read the scene:",
        ),
        (
            &["sim", &scene("projectile.ron"), "--integrator", "rk5"],
            "tickwork: --integrator rk5: no such method\n  caused by: unknown integrator 'rk5'; valid names",
        ),
        (
            &["sim", &scene("projectile.ron"), "--dt", "-0.1"],
            "tickwork: --dt -0.1: not a step the fixed clock accepts\n  caused by: invalid step in seconds: -0.1",
        ),
        (
            &["sim", &scene("projectile.ron"), "--until", "NaN"],
            "tickwork: --until: NaN is not a finite time",
        ),
        (
            &["sim", &scene("projectile.ron"), "--every", "0"],
            "tickwork: --every: must be at least 1",
        ),
    ];
    for (args, expected) in cases {
        let output = tickwork(args);
        assert!(!output.status.success(), "{args:?}");
        let message = String::from_utf8_lossy(&output.stderr);
        assert!(message.starts_with(expected), "{args:?}: {message}");
    }
}

#[test]
fn sim_traces_rigid_body_orientation_and_angular_velocity() {
    let trace = temp_path("tops.csv");
    let output = tickwork(&[
        "sim",
        &scene("tops.ron"),
        "--steps",
        "240",
        "--every",
        "120",
        "--trace",
        trace.to_str().expect("utf-8"),
    ]);
    assert!(output.status.success(), "{}", String::from_utf8_lossy(&output.stderr));
    let text = std::fs::read_to_string(&trace).expect("trace");
    let rows: Vec<Vec<f64>> = text
        .lines()
        .skip(1)
        .map(|l| l.split(',').map(|f| f.parse().expect("number")).collect())
        .collect();
    assert_eq!(rows.len(), 6, "two bodies at steps 0, 120 and 240");
    for row in &rows {
        let norm = (row[10].powi(2) + row[11].powi(2) + row[12].powi(2) + row[13].powi(2)).sqrt();
        assert!((norm - 1.0).abs() < 1e-5, "unit quaternion: {row:?}");
        if row[2] == 1.0 {
            // About its major axis: a steady spin of 4 rad/s.
            let spin = (row[14].powi(2) + row[15].powi(2) + row[16].powi(2)).sqrt();
            assert!((spin - 4.0).abs() < 0.01, "steady spin: {row:?}");
        }
    }
    // About its intermediate axis the first body starts to tumble: the
    // 0.02 rad/s off-axis seed has grown (the Dzhanibekov flip).
    let tumbling = &rows[4];
    assert_eq!(tumbling[2], 0.0);
    assert!(tumbling[16].abs() > 1.0, "off-axis spin grew: {tumbling:?}");
}

#[test]
fn rates_outside_the_range_are_errors_stating_it_never_a_silent_substitute() {
    // `--hz 5e-7` once ran at "rate 1 Hz".
    for (option, value, range) in [
        (
            "--hz",
            "5e-7",
            "accepted: from 1/3600 (a step of an hour) to 1e6 (a step of a microsecond) steps per second",
        ),
        ("--hz", "1e7", "accepted: from 1/3600"),
        (
            "--dt",
            "1e-7",
            "accepted: from 1e-6 (a microsecond) to 3600 (an hour) seconds",
        ),
        (
            "--dt",
            "3601",
            "accepted: from 1e-6 (a microsecond) to 3600 (an hour) seconds",
        ),
    ] {
        let output = tickwork(&["sim", &scene("projectile.ron"), option, value, "--until", "1"]);
        let stderr = String::from_utf8_lossy(&output.stderr);
        assert!(!output.status.success(), "{option} {value} was accepted");
        assert!(!stderr.contains("panicked at"), "{stderr}");
        assert!(
            stderr.contains(&format!("{option} {value}: ")),
            "{option} {value}: {stderr}"
        );
        assert!(stderr.contains(range), "{option} {value}: {stderr}");
    }
    let output = tickwork(&["sim", &scene("projectile.ron"), "--hz", "1e308", "--until", "1"]);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(stderr.contains("invalid rate in Hz: 1e308 (accepted"), "{stderr}");
}

#[test]
fn negative_and_non_finite_numbers_are_errors_naming_the_option_and_the_value() {
    // Negative numbers once got clap's "unexpected argument '-1'" and a
    // wrong tip.
    let projectile = scene("projectile.ron");
    let cases: [(&[&str], &str, &str); 7] = [
        (&["render", &projectile, "--frames", "-1"], "--frames", "-1"),
        (&["render", &projectile, "--size", "-5x5"], "--size", "-5x5"),
        (&["render", &projectile, "--display-hz", "-60"], "--display-hz", "-60"),
        (&["sim", &projectile, "--until", "-inf"], "--until", "-inf"),
        (&["sim", &projectile, "--hz", "-1"], "--hz", "-1"),
        (&["sim", &projectile, "--dt", "-0.01"], "--dt", "-0.01"),
        (&["view", &projectile, "--hold", "NaN"], "--hold", "NaN"),
    ];
    for (args, option, value) in cases {
        let output = tickwork(args);
        let stderr = String::from_utf8_lossy(&output.stderr);
        assert!(!output.status.success(), "{args:?} was accepted");
        assert!(
            matches!(output.status.code(), Some(1 | 2)),
            "{args:?}: {:?}",
            output.status
        );
        assert!(!stderr.contains("panicked at"), "{args:?}: {stderr}");
        assert!(!stderr.contains("unexpected argument"), "{args:?}: {stderr}");
        assert!(stderr.contains(option) && stderr.contains(value), "{args:?}: {stderr}");
    }
}

#[test]
fn runaway_and_misdirected_requests_are_errors_that_write_nothing() {
    let projectile = scene("projectile.ron");
    let dir = temp_path("misdirected");
    std::fs::create_dir_all(&dir).expect("a directory");
    let gif = temp_path("never.gif");
    let dir_text = dir.to_str().expect("utf-8");
    let gif_text = gif.to_str().expect("utf-8");
    let cases: [(&[&str], &str); 4] = [
        (
            &["sim", &projectile, "--until", "1e300"],
            "--until: 1e300 s is 6e301 steps at 60 Hz, past the limit of 10000000000 steps a run",
        ),
        (
            &["sim", &projectile, "--trace", dir_text],
            "is a directory; name a file",
        ),
        (
            &["render", &projectile, "--frames", "0", "--gif", gif_text],
            "--frames: 0 frames; pass at least 1",
        ),
        (
            &["render", &projectile, "--gif", dir_text],
            "is a directory; name a .gif file",
        ),
    ];
    for (args, expected) in cases {
        let output = tickwork(args);
        let stderr = String::from_utf8_lossy(&output.stderr);
        assert!(!output.status.success(), "{args:?} was accepted");
        assert!(!stderr.contains("panicked at"), "{args:?}: {stderr}");
        assert!(stderr.contains(expected), "{args:?}: {stderr}");
    }
    assert!(!gif.exists(), "no GIF was written for zero frames");
    assert_eq!(
        std::fs::read_dir(&dir).expect("listed").count(),
        0,
        "nothing written into the directory"
    );
}

/// The window options `tickwork view` parses from `args` (after `view`).
fn view_options(args: &[&str]) -> Result<tickwork_engine::app::WindowOptions, clap::Error> {
    use clap::Parser;
    let cli = tickwork_demos::cli::Cli::try_parse_from(["tickwork", "view"].iter().chain(args))?;
    match cli.command {
        Some(tickwork_demos::cli::Command::View(view)) => Ok(view.window_options()),
        other => panic!("`view` parsed as {other:?}"),
    }
}

#[test]
fn view_shows_the_control_panel_unless_told_not_to() {
    let kepler = scene("kepler.ron");
    let shown = view_options(&[&kepler]).expect("parses");
    assert!(shown.panel, "the lab's scenes start with their controls");
    assert_eq!((shown.width, shown.height), (1280, 720));
    assert!(view_options(&[&kepler, "--panel"]).expect("parses").panel);
    let hidden = view_options(&[&kepler, "--no-panel", "--size", "320x200"]).expect("parses");
    assert!(!hidden.panel, "--no-panel hides it");
    assert_eq!((hidden.width, hidden.height), (320, 200));
    let both = view_options(&[&kepler, "--panel", "--no-panel"]).expect_err("contradictory");
    assert_eq!(both.kind(), clap::error::ErrorKind::ArgumentConflict);
    let message = both.to_string();
    assert!(
        message.contains("--panel") && message.contains("--no-panel"),
        "{message}"
    );
    // The binary says the same, with clap's usage-error exit code.
    let output = tickwork(&["view", &kepler, "--no-panel", "--panel"]);
    assert_eq!(output.status.code(), Some(2));
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(stderr.contains("cannot be used with"), "{stderr}");
}

/// What `tickwork args...` returns, run in this process (no output is
/// printed on an error).
fn execute(args: &[&str]) -> Result<(), tickwork_demos::cli::CliError> {
    use clap::Parser;
    let cli = tickwork_demos::cli::Cli::try_parse_from(std::iter::once("tickwork").chain(args.iter().copied()))
        .expect("parses");
    tickwork_demos::cli::execute(cli)
}

#[test]
fn a_missing_scene_is_a_cli_error_whose_source_is_the_engines_scene_error() {
    use std::error::Error as _;
    use tickwork_demos::cli::CliError;
    let error = execute(&["sim", "no/such.ron"]).expect_err("no such scene");
    assert!(
        matches!(&error, CliError::SceneLoad(scene) if scene.file == "no/such.ron"),
        "{error:?}"
    );
    assert_eq!(error.to_string(), "cannot load the scene no/such.ron");
    let scene = error
        .source()
        .and_then(|s| s.downcast_ref::<tickwork_engine::SceneError>())
        .expect("the scene error is the source");
    assert_eq!(scene.file, "no/such.ron");
    assert!(scene.message.starts_with("cannot read the scene"), "{scene:?}");
    // The binary's text: the context, then the engine's message.
    let report = tickwork_demos::cli::report(&error);
    assert_eq!(
        report.lines().collect::<Vec<_>>()[..2],
        [
            "tickwork: cannot load the scene no/such.ron",
            &format!("  caused by: {scene}")
        ]
    );
}

#[test]
fn a_malformed_scene_keeps_its_line_and_field_in_the_source() {
    use std::error::Error as _;
    let path = temp_path("malformed.ron");
    std::fs::write(&path, "SceneFile(particles: [(position: (0, 2, 0), radius: \"big\")])").expect("written");
    let path_text = path.to_str().expect("utf-8");
    let error = execute(&["sim", path_text]).expect_err("malformed");
    let scene = error
        .source()
        .and_then(|s| s.downcast_ref::<tickwork_engine::SceneError>())
        .expect("the scene error is the source");
    assert_eq!(scene.file, path_text);
    assert!(scene.position.is_some(), "{scene:?}");
    let output = tickwork(&["sim", path_text]);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(stderr.contains(&format!("  caused by: {scene}")), "{stderr}");
    let _ = std::fs::remove_file(&path);
}

#[test]
fn an_unknown_integrator_is_a_variant_naming_it_with_the_registrys_error() {
    use std::error::Error as _;
    use tickwork_demos::cli::CliError;
    for command in ["sim", "view"] {
        let error = execute(&[command, &scene("projectile.ron"), "--integrator", "rk5"]).expect_err("no such method");
        let CliError::Integrator(unknown) = &error else {
            panic!("{command}: {error:?}");
        };
        assert_eq!(unknown.name, "rk5");
        assert!(unknown.valid.contains(&"rk4"), "{unknown:?}");
        assert_eq!(error.to_string(), "--integrator rk5: no such method");
        assert!(
            error
                .source()
                .and_then(|s| s.downcast_ref::<tickwork_integrators::UnknownMethod>())
                .is_some_and(|s| s == unknown),
            "{command}"
        );
    }
}

#[test]
fn a_refused_rate_names_the_option_and_keeps_the_clocks_range() {
    use std::error::Error as _;
    use tickwork_demos::cli::CliError;
    use tickwork_engine::ClockError;
    let error = execute(&["sim", &scene("projectile.ron"), "--hz", "1e7"]).expect_err("too fast");
    assert!(
        matches!(
            &error,
            CliError::Rate {
                option: "--hz",
                value,
                source: ClockError::InvalidRate { .. }
            } if *value == 1e7
        ),
        "{error:?}"
    );
    let clock = error.source().expect("the clock's error").to_string();
    assert!(clock.contains("accepted: from 1/3600"), "{clock}");
}

#[test]
fn lab_errors_keep_their_text_and_their_source() {
    use std::error::Error as _;
    use tickwork_demos::cli::CliError;
    use tickwork_demos::lab::LabError;
    // An unknown problem has no cause: one line, as before.
    let error = execute(&["lab", "convergence", "--problem", "pendulum"]).expect_err("no such problem");
    assert!(
        matches!(&error, CliError::Lab(LabError::UnknownProblem { name, .. }) if name == "pendulum"),
        "{error:?}"
    );
    assert!(error.source().is_none());
    assert_eq!(
        tickwork_demos::cli::report(&error),
        "tickwork: unknown problem 'pendulum'; valid problems are: harmonic, damped, projectile, kepler"
    );
    // An output directory under a file: the system's error is the source.
    let file = temp_path("not-a-directory");
    std::fs::write(&file, "a file").expect("written");
    let out = file.join("lab");
    let out_text = out.to_str().expect("utf-8");
    let error = execute(&["lab", "stability", "--out", out_text]).expect_err("cannot create");
    assert!(
        matches!(&error, CliError::Lab(LabError::CreateDir { path, .. }) if *path == out),
        "{error:?}"
    );
    assert_eq!(error.to_string(), format!("cannot create the directory {out_text}"));
    assert!(
        error
            .source()
            .and_then(|s| s.downcast_ref::<std::io::Error>())
            .is_some(),
        "{error:?}"
    );
    let _ = std::fs::remove_file(&file);
}

#[test]
fn a_cause_that_repeats_the_line_above_is_printed_once() {
    // `GameError::Engine` shows its source's message as its own.
    let scene = tickwork_engine::SceneError {
        file: "a.ron".into(),
        position: Some((3, 7)),
        field: "rate".into(),
        message: "invalid rate in Hz: 0".into(),
    };
    let game = tickwork_engine::app::GameError::from(scene);
    assert_eq!(
        tickwork_demos::cli::report(&game),
        "tickwork: a.ron:3:7: rate: invalid rate in Hz: 0"
    );
}

#[test]
fn sim_on_the_gpu_ends_in_the_cpus_checksum_and_refuses_what_it_does_not_do_by_name() {
    let line = |stdout: &str, name: &str| {
        stdout
            .lines()
            .find(|l| l.starts_with(name))
            .unwrap_or_else(|| panic!("no {name} line:\n{stdout}"))
            .to_owned()
    };
    for (file, extra) in [
        // 100k particles, drag, a floor with friction.
        ("rain.ron", vec!["--steps", "150"]),
        // An attractor and an immovable sun, under RK4.
        ("kepler.ron", vec!["--steps", "700", "--integrator", "rk4"]),
        // A bouncing ball, 240 Hz, under midpoint.
        ("bouncing_ball.ron", vec!["--integrator", "midpoint"]),
        // An emitter and lifetimes of 4 s: rows come and go every step.
        ("fountain.ron", vec!["--steps", "300"]),
    ] {
        let path = scene(file);
        let mut args = vec!["sim", path.as_str()];
        args.extend(extra.iter().copied());
        let cpu = tickwork(&args);
        args.push("--gpu");
        let gpu = tickwork(&args);
        for output in [&cpu, &gpu] {
            assert!(
                output.status.success(),
                "{file}: {}",
                String::from_utf8_lossy(&output.stderr)
            );
        }
        let (cpu, gpu) = (
            String::from_utf8_lossy(&cpu.stdout).into_owned(),
            String::from_utf8_lossy(&gpu.stdout).into_owned(),
        );
        assert_eq!(line(&cpu, "backend"), "backend     cpu");
        assert!(line(&gpu, "backend").starts_with("backend     gpu: "), "{gpu}");
        for name in ["checksum", "energy", "steps"] {
            assert_eq!(
                line(&gpu, name),
                line(&cpu, name),
                "{file}: the GPU's {name} against the CPU's"
            );
        }
    }
    let projectile = scene("projectile.ron");
    let refused = tickwork(&["sim", &projectile, "--gpu", "--integrator", "predictor_corrector_euler"]);
    assert!(!refused.status.success());
    assert_eq!(
        String::from_utf8_lossy(&refused.stderr).lines().next(),
        Some(
            "tickwork: --gpu: the GPU step has no method \"predictor_corrector_euler\": not on the GPU yet (these \
             are: explicit and semi-implicit Euler, midpoint, Heun, RK4, Forest-Ruth, velocity Verlet, leapfrog, \
             position Verlet, Beeman and Adams-Bashforth 2-4)"
        )
    );
}

#[test]
fn sim_on_the_gpu_traces_the_cpus_states_particle_by_particle() {
    // Read back at each traced step: the trace is the CPU's, line for line
    // (lavapipe computes as the CPU does), for a world whose rows stay and
    // for one whose emitter and lifetimes change them every step.
    for (file, extra) in [
        (
            "kepler.ron",
            vec!["--steps", "240", "--integrator", "rk4", "--every", "40"],
        ),
        ("fountain.ron", vec!["--steps", "200", "--every", "50"]),
    ] {
        let path = scene(file);
        let (cpu_trace, gpu_trace) = (
            temp_path(&format!("cpu-{file}.csv")),
            temp_path(&format!("gpu-{file}.csv")),
        );
        let (cpu_arg, gpu_arg) = (cpu_trace.display().to_string(), gpu_trace.display().to_string());
        let mut cpu = vec!["sim", path.as_str(), "--force", "--trace", cpu_arg.as_str()];
        cpu.extend(extra.iter().copied());
        let mut gpu = vec!["sim", path.as_str(), "--force", "--gpu", "--trace", gpu_arg.as_str()];
        gpu.extend(extra.iter().copied());
        let (cpu, gpu) = (tickwork(&cpu), tickwork(&gpu));
        for output in [&cpu, &gpu] {
            assert!(
                output.status.success(),
                "{file}: {}",
                String::from_utf8_lossy(&output.stderr)
            );
        }
        let stdout = String::from_utf8_lossy(&gpu.stdout);
        let reads = stdout
            .lines()
            .find(|l| l.starts_with("backend"))
            .unwrap_or_else(|| panic!("a backend line: {stdout}"));
        let traced = 1 + extra.iter().position(|a| *a == "--every").expect("--every");
        let times = extra[1].parse::<u64>().expect("steps") / extra[traced].parse::<u64>().expect("every");
        assert!(
            reads.contains(&format!("read back at the end and for the trace {times} times, ")),
            "{reads}"
        );
        let (a, b) = (
            std::fs::read_to_string(&cpu_trace).expect("the CPU's trace"),
            std::fs::read_to_string(&gpu_trace).expect("the GPU's trace"),
        );
        assert_eq!(a.lines().count(), b.lines().count(), "{file}: the traces' lines");
        assert!(
            a.lines().count() > 1 + times as usize,
            "{file}: a trace of the particles"
        );
        for (n, (c, g)) in a.lines().zip(b.lines()).enumerate() {
            assert_eq!(g, c, "{file}: line {} of the GPU's trace against the CPU's", n + 1);
        }
    }
}

/// A scratch crate in the system's temporary folder (outside this
/// workspace): `files` as (path, text).
fn scratch_crate(name: &str, files: &[(&str, &str)]) -> std::path::PathBuf {
    let dir = std::env::temp_dir().join(format!("tickwork-cli-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    for (path, text) in files {
        let path = dir.join(path);
        std::fs::create_dir_all(path.parent().expect("a folder")).expect("the folder");
        std::fs::write(path, text).expect("the file");
    }
    dir
}

/// The checkout's root, for a path dependency on tickwork.
fn checkout() -> String {
    std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("..")
        .canonicalize()
        .expect("the checkout")
        .display()
        .to_string()
}

fn manifest(name: &str, dependency: &str) -> String {
    format!("[package]\nname = \"{name}\"\nversion = \"0.1.0\"\nedition = \"2024\"\n\n[dependencies]\n{dependency}\n")
}

/// `tickwork web build` on `dir`, into `out`: its exit status and stderr.
fn web_build(dir: &std::path::Path, out: &std::path::Path, extra: &[&str]) -> (bool, String) {
    let manifest = dir.join("Cargo.toml");
    let mut args = vec![
        "web",
        "build",
        "--manifest-path",
        manifest.to_str().expect("utf-8"),
        "--out",
    ];
    args.push(out.to_str().expect("utf-8"));
    args.extend(extra);
    let output = tickwork(&args);
    (
        output.status.success(),
        String::from_utf8_lossy(&output.stderr).into_owned(),
    )
}

#[test]
fn web_build_refuses_a_crate_that_cannot_be_a_page_before_building_anything() {
    let tickwork_dep = format!("tickwork = {{ path = {:?} }}", checkout());
    let main = "fn main() {}\n";
    // (name, files, extra arguments, what the error says)
    type Case<'a> = (&'a str, Vec<(&'a str, String)>, &'a [&'a str], &'a str);
    let cases: [Case<'_>; 4] = [
        (
            "nogame",
            vec![("Cargo.toml", manifest("nogame", "")), ("src/main.rs", main.into())],
            &[],
            "nogame (",
        ),
        (
            "nobin",
            vec![
                ("Cargo.toml", manifest("nobin", &tickwork_dep)),
                ("src/lib.rs", String::new()),
            ],
            &[],
            "nobin has no binary (",
        ),
        (
            "twobins",
            vec![
                ("Cargo.toml", manifest("twobins", &tickwork_dep)),
                ("src/bin/a.rs", main.into()),
                ("src/bin/b.rs", main.into()),
            ],
            &[],
            "tickwork: twobins has 2 binaries (a, b): pass --bin NAME for each page to build",
        ),
        (
            "nosuchbin",
            vec![
                ("Cargo.toml", manifest("nosuchbin", &tickwork_dep)),
                ("src/main.rs", main.into()),
            ],
            &["--bin", "other"],
            "tickwork: --bin other: nosuchbin has no such binary (it has: nosuchbin)",
        ),
    ];
    for (name, files, extra, expected) in cases {
        let files: Vec<(&str, &str)> = files.iter().map(|(p, t)| (*p, t.as_str())).collect();
        let dir = scratch_crate(name, &files);
        let out = dir.join("site");
        let (ok, stderr) = web_build(&dir, &out, extra);
        assert!(!ok, "{name}: refused");
        assert!(stderr.contains(expected), "{name}: {stderr}");
        assert!(!out.exists(), "{name}: nothing written");
        assert!(!dir.join("target").exists(), "{name}: nothing built");
        let _ = std::fs::remove_dir_all(&dir);
    }
    let dir = scratch_crate(
        "nogame-text",
        &[("Cargo.toml", &manifest("plain", "")), ("src/main.rs", main)],
    );
    let (_, stderr) = web_build(&dir, &dir.join("site"), &[]);
    assert!(
        stderr.contains("depends on neither tickwork nor tickwork-engine, so it has no Game to build a page of"),
        "{stderr}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn web_build_never_overwrites_a_folder_of_other_files() {
    let tickwork_dep = format!("tickwork = {{ path = {:?} }}", checkout());
    let dir = scratch_crate(
        "notours",
        &[
            ("Cargo.toml", &manifest("notours", &tickwork_dep)),
            ("src/main.rs", "fn main() {}\n"),
            ("site/mine.txt", "mine"),
        ],
    );
    let (ok, stderr) = web_build(&dir, &dir.join("site"), &[]);
    assert!(!ok);
    assert!(
        stderr.contains("the folder holds files no web build wrote, and nothing was overwritten"),
        "{stderr}"
    );
    assert_eq!(
        std::fs::read_to_string(dir.join("site/mine.txt")).expect("kept"),
        "mine"
    );
    assert!(!dir.join("target").exists(), "nothing built");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn new_writes_a_game_crate_and_never_into_a_folder_that_is_not_empty() {
    let dir = scratch_crate("new-full", &[("notes.txt", "mine")]);
    let output = tickwork(&["new", dir.to_str().expect("utf-8")]);
    assert!(!output.status.success());
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(
        stderr.contains("the folder is not empty, and nothing was written"),
        "{stderr}"
    );
    assert_eq!(std::fs::read_to_string(dir.join("notes.txt")).expect("kept"), "mine");
    assert!(!dir.join("Cargo.toml").exists());

    let game = dir.with_file_name(format!("tickwork-cli-{}-space-race", std::process::id()));
    let _ = std::fs::remove_dir_all(&game);
    let output = tickwork(&["new", game.to_str().expect("utf-8"), "--name", "space-race"]);
    assert!(output.status.success(), "{}", String::from_utf8_lossy(&output.stderr));
    let stdout = String::from_utf8_lossy(&output.stdout);
    assert!(
        stdout.contains("tickwork web serve --release"),
        "it says what to run next: {stdout}"
    );
    let cargo_toml = std::fs::read_to_string(game.join("Cargo.toml")).expect("Cargo.toml");
    assert!(cargo_toml.contains("name = \"space-race\""), "{cargo_toml}");
    assert!(
        cargo_toml.contains(&format!("tickwork = {{ path = {:?} }}", checkout())),
        "{cargo_toml}"
    );
    let lib = std::fs::read_to_string(game.join("src/lib.rs")).expect("src/lib.rs");
    assert!(
        lib.contains("pub struct SpaceRaceGame") && lib.contains("\"space-race\""),
        "{lib}"
    );
    let main = std::fs::read_to_string(game.join("src/main.rs")).expect("src/main.rs");
    assert!(main.contains("space_race::SpaceRaceGame::default()"), "{main}");
    let recording = std::fs::read_to_string(game.join("recordings/kicks.ron")).expect("the recording");
    assert!(recording.contains("game: \"space-race\""), "{recording}");
    for file in [
        "tests/game.rs",
        "tests/golden/first_second.png",
        "README.md",
        ".gitignore",
        "Cargo.lock",
    ] {
        assert!(game.join(file).is_file(), "{file} written");
    }
    let png = std::fs::read(game.join("tests/golden/first_second.png")).expect("the golden image");
    assert!(png.starts_with(b"\x89PNG"), "the golden image is a PNG");
    // A second time into the same folder: refused, nothing changed.
    let output = tickwork(&["new", game.to_str().expect("utf-8")]);
    assert!(!output.status.success());
    assert_eq!(
        std::fs::read_to_string(game.join("Cargo.toml")).expect("kept"),
        cargo_toml
    );
    let output = tickwork(&["new", dir.with_file_name("9lives").to_str().expect("utf-8")]);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(
        stderr.contains("\"9lives\" cannot name a crate: it must start with a letter; pass --name NAME"),
        "{stderr}"
    );
    assert!(!dir.with_file_name("9lives").exists());
    let _ = std::fs::remove_dir_all(&dir);
    let _ = std::fs::remove_dir_all(&game);
}
