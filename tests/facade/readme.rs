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
        number_after(&text, "a platformer in ", " lines"),
        lines_of("demos/src/platformer.rs") + lines_of("demos/src/bin/platformer.rs"),
        "the platformer's lines, options and main included"
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

#[test]
fn the_changelog_has_one_section_of_each_kind_per_version() {
    let text = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/CHANGELOG.md")).expect("CHANGELOG.md");
    // Each version (`## [..]`) lists its changes under Keep a Changelog's
    // headings, each at most once, breaking changes under one of them.
    for version in text.split("\n## ").skip(1) {
        let name = version.lines().next().unwrap_or_default();
        let mut seen: Vec<&str> = Vec::new();
        for heading in version.lines().filter_map(|l| l.strip_prefix("### ")) {
            assert!(!seen.contains(&heading), "{name}: two sections {heading:?}");
            assert!(
                [
                    "Added",
                    "Breaking",
                    "Changed",
                    "Deprecated",
                    "Removed",
                    "Fixed",
                    "Security"
                ]
                .contains(&heading),
                "{name}: a section {heading:?}, not one of Keep a Changelog's (breaking changes go under \"Breaking\")"
            );
            seen.push(heading);
        }
    }
}

/// The repository's files under `dir` whose name ends with one of `ext`.
fn files_under(dir: &std::path::Path, ext: &[&str], out: &mut Vec<std::path::PathBuf>) {
    let entries = std::fs::read_dir(dir).unwrap_or_else(|e| panic!("{}: {e}", dir.display()));
    for entry in entries {
        let path = entry.expect("a directory entry").path();
        if path.is_dir() {
            files_under(&path, ext, out);
        } else if ext.iter().any(|e| path.extension().is_some_and(|x| x == *e)) {
            out.push(path);
        }
    }
}

#[test]
fn no_source_file_is_over_600_lines() {
    // One concept per file: a file past 600 lines is split along its
    // seams. Pure test files (`tests.rs`, `tests/`) are exempt.
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut files = Vec::new();
    for dir in [
        "src",
        "integrators/src",
        "engine/src",
        "engine/shaders",
        "demos/src",
        "fuzz",
    ] {
        files_under(&root.join(dir), &["rs", "wgsl"], &mut files);
    }
    assert!(files.len() > 150, "the sources: {}", files.len());
    let long: Vec<String> = files
        .iter()
        .filter(|f| f.file_name().is_some_and(|n| n != "tests.rs"))
        .filter(|f| {
            !f.components()
                .any(|c| c.as_os_str() == "tests" || c.as_os_str() == "target")
        })
        .filter_map(|f| {
            let lines = std::fs::read_to_string(f).expect("a source file").lines().count();
            (lines > 600).then(|| format!("{} ({lines} lines)", f.strip_prefix(root).unwrap_or(f).display()))
        })
        .collect();
    assert!(long.is_empty(), "files over 600 lines: {long:?}");
}

#[test]
fn the_map_and_the_performance_page_stay_short() {
    assert!(
        lines_of("ARCHITECTURE.md") <= 400,
        "ARCHITECTURE.md is a map: {} lines",
        lines_of("ARCHITECTURE.md")
    );
    assert!(
        lines_of("docs/performance.md") <= 400,
        "docs/performance.md: {} lines",
        lines_of("docs/performance.md")
    );
}

/// GitHub's anchor for a heading: lower case, spaces to `-`, punctuation
/// other than `-` and `_` dropped.
fn anchor(heading: &str) -> String {
    heading
        .trim()
        .to_lowercase()
        .chars()
        .filter_map(|c| match c {
            ' ' => Some('-'),
            c if c.is_alphanumeric() || c == '-' || c == '_' => Some(c),
            _ => None,
        })
        .collect()
}

#[test]
fn the_docs_links_resolve() {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut docs = vec![
        root.join("README.md"),
        root.join("ARCHITECTURE.md"),
        root.join("CHANGELOG.md"),
    ];
    files_under(&root.join("docs"), &["md"], &mut docs);
    let mut broken = Vec::new();
    let mut checked = 0;
    for doc in &docs {
        let text = std::fs::read_to_string(doc).expect("a doc");
        let mut in_code = false;
        for (n, line) in text.lines().enumerate() {
            if line.trim_start().starts_with("```") {
                in_code = !in_code;
            }
            if in_code {
                continue;
            }
            for (at, _) in line.match_indices("](") {
                let rest = &line[at + 2..];
                let Some(end) = rest.find(')') else { continue };
                let target = &rest[..end];
                if target.contains("://") || target.starts_with("mailto:") || target.contains(' ') {
                    continue;
                }
                let (file, fragment) = target.split_once('#').unwrap_or((target, ""));
                let path = if file.is_empty() {
                    doc.clone()
                } else {
                    doc.parent().expect("a folder").join(file)
                };
                checked += 1;
                let place = format!(
                    "{}:{}: {target}",
                    doc.strip_prefix(root).unwrap_or(doc).display(),
                    n + 1
                );
                if !path.exists() {
                    broken.push(format!("{place} (no such file)"));
                    continue;
                }
                if !fragment.is_empty() && path.extension().is_some_and(|e| e == "md") {
                    let target_text = std::fs::read_to_string(&path).expect("a linked doc");
                    let found = target_text
                        .lines()
                        .filter_map(|l| l.strip_prefix('#').map(|h| h.trim_start_matches('#')))
                        .any(|h| anchor(h) == fragment);
                    if !found {
                        broken.push(format!("{place} (no heading #{fragment})"));
                    }
                }
            }
        }
    }
    assert!(checked > 50, "links checked: {checked}");
    assert!(broken.is_empty(), "broken links:\n{}", broken.join("\n"));
}

/// `n` as the docs write it in words.
fn in_words(n: usize) -> &'static str {
    const WORDS: [&str; 21] = [
        "zero",
        "one",
        "two",
        "three",
        "four",
        "five",
        "six",
        "seven",
        "eight",
        "nine",
        "ten",
        "eleven",
        "twelve",
        "thirteen",
        "fourteen",
        "fifteen",
        "sixteen",
        "seventeen",
        "eighteen",
        "nineteen",
        "twenty",
    ];
    WORDS.get(n).copied().unwrap_or("many")
}

fn read(path: &str) -> String {
    let file = format!("{}/{path}", env!("CARGO_MANIFEST_DIR"));
    std::fs::read_to_string(&file).unwrap_or_else(|e| panic!("{file}: {e}"))
}

#[test]
fn the_docs_numbers_of_the_gpu_step_are_the_codes() {
    // The methods the GPU step takes, as the guide and the design doc count them.
    let methods = tickwork::engine::gpu_step::methods().count();
    let word = in_words(methods);
    assert!(
        read("docs/guide.md").contains(&format!("the {word} explicit methods of the lecture")),
        "the guide counts the GPU step's {methods} methods"
    );
    assert!(
        read("docs/design/gpu-step.md").contains(&format!("- The {word} methods above.")),
        "the design doc counts the GPU step's {methods} methods"
    );
    // Each is a registered method, under its canonical name.
    for method in tickwork::engine::gpu_step::methods() {
        let found = tickwork::integrators::find(method).map(|info| info.name);
        assert_eq!(found.ok(), Some(method), "{method}: a registered method");
    }
    // The storage buffers a stage binds: the step's shader declares them.
    let buffers = read("engine/shaders/gpu_step/step.wgsl").matches("var<storage").count();
    assert!(
        read("docs/design/gpu-step.md").contains(&format!("the step binds {buffers} storage buffers a stage")),
        "the design doc says the step binds {buffers} storage buffers"
    );
}
