//! The README states the registry and the two commands; keep it true.

use tickwork::integrators::METHODS;

fn readme() -> String {
    std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/README.md")).expect("README.md")
}

#[test]
fn the_readme_method_table_matches_the_registry() {
    let text = readme();
    let rows: Vec<Vec<&str>> = text
        .lines()
        .filter(|l| l.starts_with("| ") && l.matches('|').count() == 7)
        .map(|l| l.trim_matches('|').split('|').map(str::trim).collect())
        .filter(|cells: &Vec<&str>| METHODS.iter().any(|m| m.name == cells[0]))
        .collect();
    assert_eq!(rows.len(), METHODS.len(), "one README row per registered method");
    for (row, info) in rows.iter().zip(METHODS) {
        assert_eq!(row[0], info.name, "README rows follow the registry's order");
        let orders = format!("{}/{}/{}", info.order, info.order_velocity, info.order_velocity_forces);
        assert_eq!(row[1], orders, "{}: orders", info.name);
        let evaluations = format!("{}{}", info.evaluations, if info.variable_cost { "+" } else { "" });
        assert_eq!(row[2], evaluations, "{}: evaluations", info.name);
        assert_eq!(row[3] == "yes", info.symplectic, "{}: symplectic", info.name);
        assert_eq!(row[4] == "yes", info.reversible, "{}: reversible", info.name);
    }
}

#[test]
fn the_readme_gives_the_two_commands_ci_runs() {
    let text = readme();
    assert!(text.contains("cargo run --release "), "the main job");
    assert!(text.contains("scripts/test "), "the test command");
    let ci = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/.ci/run")).expect(".ci/run");
    assert!(
        ci.lines().any(|l| l.trim() == "scripts/test"),
        "CI calls the README's test command"
    );
}
