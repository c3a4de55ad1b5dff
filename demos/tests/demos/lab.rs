//! `tickwork lab all`: every file is written, the plots decode as non-blank
//! PNGs, and the data match theory: fitted convergence slopes against the
//! registry's orders, stability limits against theory, bounded energy for the
//! symplectic methods; an elastic ball keeps its height with contacts inside
//! the step and gains it with contacts at the end.
// Reference values and set-ups computed natively (never in a page): the
// platform's own functions are fine here (clippy.toml bans them in the engine).
#![allow(clippy::disallowed_methods)]

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::Command;

use tickwork_integrators::{METHODS, find};

fn lab(args: &[&str]) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_tickwork"))
        .arg("lab")
        .args(args)
        .output()
        .expect("runs")
}

fn out_dir(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("tickwork-lab-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    dir
}

fn csv(path: &Path) -> Vec<Vec<String>> {
    let text = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    text.lines()
        .skip(1)
        .map(|l| l.split(',').map(str::to_owned).collect())
        .collect()
}

/// Least-squares slope of ln(error) against ln(dt), over errors above 1e-12.
fn slope(points: &[(f64, f64)]) -> Option<f64> {
    let pts: Vec<(f64, f64)> = points
        .iter()
        .filter(|p| p.1.is_finite() && p.1 > 1e-12)
        .map(|p| (p.0.ln(), p.1.ln()))
        .collect();
    if pts.len() < 3 {
        return None;
    }
    let n = pts.len() as f64;
    let (mx, my) = (
        pts.iter().map(|p| p.0).sum::<f64>() / n,
        pts.iter().map(|p| p.1).sum::<f64>() / n,
    );
    let sxy: f64 = pts.iter().map(|p| (p.0 - mx) * (p.1 - my)).sum();
    let sxx: f64 = pts.iter().map(|p| (p.0 - mx).powi(2)).sum();
    Some(sxy / sxx)
}

fn assert_non_blank_png(path: &Path) {
    let file = std::fs::File::open(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let mut reader = png::Decoder::new(std::io::BufReader::new(file))
        .read_info()
        .expect("a PNG");
    let mut pixels = vec![0; reader.output_buffer_size().expect("size")];
    let info = reader.next_frame(&mut pixels).expect("decodes");
    assert!(
        info.width >= 800 && info.height >= 600,
        "{}: {}x{}",
        path.display(),
        info.width,
        info.height
    );
    let channels = info.line_size / info.width as usize;
    let drawn = pixels
        .chunks(channels)
        .filter(|p| p[..3].iter().any(|&c| c < 200))
        .count();
    let fraction = drawn as f64 / (info.width * info.height) as f64;
    assert!(
        fraction > 0.01,
        "{}: only {:.4} of the pixels are drawn",
        path.display(),
        fraction
    );
}

#[test]
fn lab_all_writes_every_file_and_the_data_match_theory() {
    let dir = out_dir("all");
    let output = lab(&["all", "--out", dir.to_str().expect("utf-8")]);
    assert!(output.status.success(), "{}", String::from_utf8_lossy(&output.stderr));
    let listed = String::from_utf8(output.stdout).expect("utf-8");
    let expected = [
        "convergence-harmonic.png",
        "convergence-damped.png",
        "convergence-projectile.png",
        "convergence-kepler.png",
        "convergence.csv",
        "convergence.md",
        "convergence-gpu.csv",
        "convergence-gpu.md",
        "energy.png",
        "energy.csv",
        "energy.md",
        "stability-oscillator.png",
        "stability-drag.png",
        "stability.csv",
        "stability.md",
        "cost-harmonic.png",
        "cost-damped.png",
        "cost-projectile.png",
        "cost-kepler.png",
        "cost.csv",
        "cost.md",
        "bounce.png",
        "bounce-energy.png",
        "bounce.csv",
        "bounce.md",
        "report.md",
    ];
    for name in expected {
        let path = dir.join(name);
        assert!(
            listed.contains(&format!("wrote {}", path.display())),
            "{name} not reported"
        );
        assert!(path.is_file(), "{name} not written");
        if name.ends_with(".png") {
            assert_non_blank_png(&path);
        }
    }
    let report = std::fs::read_to_string(dir.join("report.md")).expect("report");
    for png in expected.iter().filter(|n| n.ends_with(".png")) {
        assert!(report.contains(&format!("]({png})")), "report.md embeds {png}");
    }

    // Convergence: slopes refitted here from the CSV, against the registry.
    let mut runs: BTreeMap<(String, String), Vec<(f64, f64)>> = BTreeMap::new();
    for row in csv(&dir.join("convergence.csv")) {
        let point = (row[2].parse().expect("dt"), row[3].parse().expect("error"));
        runs.entry((row[0].clone(), row[1].clone())).or_default().push(point);
    }
    assert_eq!(runs.len(), 4 * METHODS.len());
    let mut wrong = Vec::new();
    for ((problem, method), points) in &runs {
        let info = find(method).expect("registered");
        let stated = match problem.as_str() {
            "harmonic" | "kepler" => info.order,
            _ => info.order_velocity_forces,
        } as f64;
        let fitted = slope(points);
        let ok = match (problem.as_str(), method.as_str(), fitted) {
            // On the nonlinear problems Dormand-Prince's fifth-order error
            // term is small beside the sixth at every step above round-off
            // (slope 6.6 on the projectile, 5.15 on the orbit): at least its order.
            ("projectile" | "kepler", "dormand_prince", Some(s)) => s >= stated - 0.15,
            (_, _, Some(s)) => (s - stated).abs() <= 0.15,
            (_, _, None) => false,
        };
        if !ok {
            wrong.push(format!("{problem} {method}: stated {stated}, fitted {fitted:?}"));
        }
    }
    assert!(wrong.is_empty(), "{}", wrong.join("\n"));

    // The GPU column: the projectile in f32 on the CPU and on the GPU, the
    // same errors on lavapipe (CI's adapter), and the slopes of the
    // registry where the errors are above f32 round-off.
    let gpu = std::fs::read_to_string(dir.join("convergence-gpu.md")).expect("convergence-gpu.md");
    assert!(gpu.contains("Adapter: "), "{gpu}");
    assert!(report.contains("### On the GPU"), "report.md has the GPU column");
    let mut gpu_methods = 0;
    let mut costs = BTreeMap::new();
    for line in gpu
        .lines()
        .filter(|l| l.starts_with("| ") && !l.starts_with("| method"))
    {
        let cells: Vec<&str> = line.split('|').map(str::trim).collect();
        // | method | stated / CPU f32 / GPU | same errors |
        let numbers: Vec<&str> = cells[2].split(" / ").collect();
        let (stated, cpu, on_gpu) = (numbers[0], numbers[1], numbers[2]);
        assert_eq!(cpu, on_gpu, "{line}");
        assert_eq!(cells[3], "yes", "{line}");
        // | evaluations for 1e-3: CPU f32 / GPU | for 1e-4: CPU f32 / GPU |
        for cost in [cells[4], cells[5]] {
            let (cpu, on_gpu) = cost.split_once(" / ").unwrap_or_else(|| panic!("{line}"));
            assert_eq!(cpu, on_gpu, "the GPU's cost is the CPU f32 world's: {line}");
        }
        costs.insert(
            cells[1].to_owned(),
            cells[5].split(" / ").next().unwrap_or("-").to_owned(),
        );
        if let (Ok(stated), Ok(fitted)) = (stated.parse::<f64>(), on_gpu.parse::<f64>()) {
            assert!((fitted - stated).abs() <= 0.25, "{line}");
        }
        gpu_methods += 1;
    }
    assert_eq!(gpu_methods, 13, "{gpu}");
    // At 1e-4, RK4 reaches it in fewer evaluations than midpoint, and
    // midpoint in fewer than explicit Euler (or Euler not at all).
    let evaluations = |method: &str| {
        costs[method]
            .trim_start_matches("at most ")
            .parse::<f64>()
            .unwrap_or(f64::INFINITY)
    };
    assert!(
        evaluations("rk4") < evaluations("midpoint") && evaluations("midpoint") < evaluations("explicit_euler"),
        "{costs:?}"
    );
    let gpu_points = csv(&dir.join("convergence-gpu.csv"));
    assert_eq!(gpu_points.len(), 13 * 5);
    assert!(gpu_points.iter().all(|row| row[3] == row[4]), "CPU f32 and GPU errors");

    // Stability: measured against theory within 2%.
    let mut checked = 0;
    let mut limits = BTreeMap::new();
    for row in csv(&dir.join("stability.csv")) {
        let measured: f64 = row[2].parse().expect("measured");
        limits.insert((row[0].clone(), row[1].clone()), measured);
        let Ok(theory) = row[3].parse::<f64>() else { continue };
        checked += 1;
        let ok = if theory == 0.0 {
            measured < 0.02 // weakly unstable methods show a tiny limit
        } else if theory.is_infinite() {
            measured.is_infinite()
        } else {
            (measured / theory - 1.0).abs() <= 0.02
        };
        assert!(ok, "{} on {}: measured {measured}, theory {theory}", row[0], row[1]);
    }
    assert!(checked >= 34, "{checked} limits have a theory value");
    let oscillator = |m: &str| limits[&(m.to_owned(), "oscillator (h omega)".to_owned())];
    assert_eq!(
        oscillator("explicit_euler"),
        0.0,
        "explicit Euler is unstable for every h"
    );
    for m in ["semi_implicit_euler", "velocity_verlet"] {
        assert!((oscillator(m) - 2.0).abs() < 0.04, "{m}: {}", oscillator(m));
    }
    assert!((oscillator("rk4") - 2.83).abs() < 0.03, "rk4: {}", oscillator("rk4"));

    // Energy: bounded for every symplectic method; explicit Euler loses the orbit.
    let energy = std::fs::read_to_string(dir.join("energy.md")).expect("energy.md");
    for info in METHODS.iter().filter(|m| m.symplectic) {
        let row = energy
            .lines()
            .find(|l| l.starts_with(&format!("| {} |", info.name)))
            .expect("row");
        assert!(row.ends_with("| bounded |"), "{row}");
    }
    let euler = energy
        .lines()
        .find(|l| l.starts_with("| explicit_euler |"))
        .expect("row");
    assert!(euler.ends_with("| lost the orbit |"), "{euler}");
    std::fs::remove_dir_all(&dir).expect("clean up");
}

#[test]
fn lab_refuses_to_overwrite_and_names_bad_problems() {
    let dir = out_dir("errors");
    let output = lab(&["stability", "--out", dir.to_str().expect("utf-8")]);
    assert!(output.status.success(), "{}", String::from_utf8_lossy(&output.stderr));
    let again = lab(&["stability", "--out", dir.to_str().expect("utf-8")]);
    assert!(!again.status.success());
    let message = String::from_utf8_lossy(&again.stderr);
    assert!(
        message.contains("stability-oscillator.png: exists; pass --force to overwrite"),
        "{message}"
    );
    assert!(
        lab(&["stability", "--out", dir.to_str().expect("utf-8"), "--force"])
            .status
            .success()
    );
    let bad = lab(&[
        "convergence",
        "--problem",
        "pendulum",
        "--out",
        dir.to_str().expect("utf-8"),
    ]);
    assert!(!bad.status.success());
    assert_eq!(
        String::from_utf8_lossy(&bad.stderr),
        "tickwork: unknown problem 'pendulum'; valid problems are: harmonic, damped, projectile, kepler\n"
    );
    let one = lab(&["cost", "--problem", "kepler", "--out", dir.to_str().expect("utf-8")]);
    assert!(one.status.success());
    assert!(dir.join("cost-kepler.png").is_file() && !dir.join("cost-harmonic.png").exists());
    std::fs::remove_dir_all(&dir).expect("clean up");
}

#[test]
fn lab_bounce_keeps_the_height_in_step_and_needs_force_to_overwrite() {
    let dir = out_dir("bounce");
    let out = dir.to_str().expect("utf-8");
    let output = lab(&["bounce", "--out", out]);
    assert!(output.status.success(), "{}", String::from_utf8_lossy(&output.stderr));
    let listed = String::from_utf8(output.stdout).expect("utf-8");
    for name in ["bounce.png", "bounce-energy.png", "bounce.csv", "bounce.md"] {
        let path = dir.join(name);
        assert!(
            listed.contains(&format!("wrote {}", path.display())),
            "{name} not reported"
        );
        assert!(path.is_file(), "{name} not written");
        if name.ends_with(".png") {
            assert_non_blank_png(&path);
        }
    }
    assert!(!dir.join("energy.png").exists(), "only the bounce study's files");

    // The apexes of every method under each rule, bounce by bounce.
    let mut apexes: BTreeMap<(String, String), Vec<f64>> = BTreeMap::new();
    for row in csv(&dir.join("bounce.csv")) {
        let bounce: usize = row[2].parse().expect("bounce");
        let run = apexes.entry((row[0].clone(), row[1].clone())).or_default();
        assert_eq!(bounce, run.len() + 1, "{row:?}: bounces in order");
        run.push(row[4].parse().expect("apex"));
    }
    for info in METHODS {
        for rule in ["end_of_step", "in_step"] {
            let run = apexes.get(&(info.name.to_owned(), rule.to_owned()));
            assert!(run.is_some(), "no rows for {} {rule}", info.name);
        }
    }
    assert_eq!(apexes.len(), 2 * METHODS.len());
    let run = |m: &str, rule: &str| &apexes[&(m.to_owned(), rule.to_owned())];
    // Velocity Verlet is exact for constant gravity; bouncing at the instant
    // of contact keeps it so over 100 bounces.
    let verlet = run("velocity_verlet", "in_step");
    assert_eq!(verlet.len(), 100);
    assert!(
        (verlet[99] - 10.0).abs() < 1e-4,
        "apex after 100 bounces {}",
        verlet[99]
    );
    // At the end of the step it gains height at every bounce.
    let verlet_end = run("velocity_verlet", "end_of_step");
    assert!(verlet_end[3] > 10.5, "after 4 bounces: {:?}", &verlet_end[..4]);
    // Semi-implicit Euler keeps its own energy: the apex, read where it
    // turns, within g dt^2 / 2 (1.4 mm) of 10 m at every bounce.
    let euler = run("semi_implicit_euler", "in_step");
    assert_eq!(euler.len(), 100);
    let worst = euler.iter().map(|a| (a - 10.0).abs()).fold(0.0, f64::max);
    assert!(worst < 1.5e-3, "worst apex {worst} m off 10 m");

    let md = std::fs::read_to_string(dir.join("bounce.md")).expect("bounce.md");
    assert!(md.contains("](bounce.png)") && md.contains("](bounce-energy.png)"));
    for info in METHODS {
        assert!(
            md.contains(&format!("\n| {} |", info.name)),
            "{} in the table",
            info.name
        );
    }

    let again = lab(&["bounce", "--out", out]);
    assert!(!again.status.success());
    let message = String::from_utf8_lossy(&again.stderr);
    assert!(
        message.contains("bounce.png: exists; pass --force to overwrite"),
        "{message}"
    );
    assert!(lab(&["bounce", "--out", out, "--force"]).status.success());
    std::fs::remove_dir_all(&dir).expect("clean up");
}
