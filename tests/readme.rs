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

/// The number before `unit` that follows `lead` in the README.
fn number_after(text: &str, lead: &str, unit: &str) -> usize {
    let at = text.find(lead).unwrap_or_else(|| panic!("the README says {lead:?}")) + lead.len();
    let rest = &text[at..];
    let end = rest.find(unit).unwrap_or_else(|| panic!("{unit:?} after {lead:?}"));
    rest[..end]
        .trim()
        .parse()
        .unwrap_or_else(|_| panic!("a number between {lead:?} and {unit:?}: {:?}", &rest[..end]))
}

/// Lines of a file of the repository.
fn lines_of(path: &str) -> usize {
    let file = format!("{}/{path}", env!("CARGO_MANIFEST_DIR"));
    std::fs::read_to_string(&file)
        .unwrap_or_else(|e| panic!("{file}: {e}"))
        .lines()
        .count()
}

#[test]
fn the_readme_line_counts_are_the_files() {
    let text = readme();
    assert_eq!(
        number_after(&text, "Breakout in ", " lines"),
        lines_of("demos/src/breakout.rs") + lines_of("demos/src/bin/breakout.rs"),
        "Breakout's lines, options and main included"
    );
    assert_eq!(
        number_after(&text, "(`demos/src/rally.rs`, ", " lines)"),
        lines_of("demos/src/rally.rs"),
        "rally's lines"
    );
    // "A game in under N lines": the section's first Rust block.
    let under = number_after(&text, "## A game in under ", " lines");
    let section = &text[text.find("## A game in under").expect("the section")..];
    // After the fence's info string (`rust`, `rust,no_run`), to the fence
    // that closes it.
    let block = section.split("```rust").nth(1).expect("its code");
    let code = block[block.find('\n').expect("a fence line")..]
        .split("```")
        .next()
        .expect("closed");
    let lines = code.trim_matches('\n').lines().count();
    assert!(
        lines < under,
        "the game is {lines} lines, the heading says under {under}"
    );
}
