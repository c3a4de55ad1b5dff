//! The modules of `engine/src` import one another without a cycle, as
//! ARCHITECTURE.md says (data flows one way): read from the source, every
//! `crate::`, `super::` and `self::` path is resolved to the module that
//! defines what it names (through the re-exports of `lib.rs` and of each
//! `mod.rs`; an item re-exported from outside the crate counts as the
//! re-exporting module's), and the graph that makes is checked for cycles
//! between the engine's top-level modules and at each level of folders
//! within them. In `app/`, no module uses an item its folder's `mod.rs`
//! defines, and each optional feature's crates are named only in its own
//! folder.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

/// A module's path below `src`, as folders: `[]` is `lib.rs`,
/// `["app", "window", "surface"]` is `app/window/surface.rs`.
type Module = Vec<String>;

/// Every module of the engine with its source (up to its tests).
fn modules() -> BTreeMap<Module, String> {
    fn walk(dir: &Path, prefix: &Module, out: &mut BTreeMap<Module, String>) {
        let mut entries: Vec<PathBuf> = std::fs::read_dir(dir)
            .expect("src/ is readable")
            .map(|entry| entry.expect("an entry").path())
            .collect();
        entries.sort();
        for path in entries {
            let name = path
                .file_stem()
                .and_then(|s| s.to_str())
                .expect("a UTF-8 name")
                .to_owned();
            if path.is_dir() {
                let mut module = prefix.clone();
                module.push(name);
                walk(&path, &module, out);
            } else if path.extension().is_some_and(|e| e == "rs") {
                // A module's tests in a file of their own (`mod tests;`)
                // are left out of the graph, as an inline `mod tests` is
                // below: they import what they test with, not the
                // module's design.
                if name == "tests" {
                    continue;
                }
                let mut module = prefix.clone();
                if name != "mod" && !(prefix.is_empty() && name == "lib") {
                    module.push(name);
                }
                let text = std::fs::read_to_string(&path).expect("readable source");
                // A `mod tests` says `super::` of its own file: not an import.
                let code = text.split("#[cfg(test)]\nmod ").next().unwrap_or_default();
                let code: String = code
                    .lines()
                    .filter(|l| !l.trim_start().starts_with("//"))
                    .map(|l| format!("{l}\n"))
                    .collect();
                out.insert(module, code);
            }
        }
    }
    let mut out = BTreeMap::new();
    walk(
        &Path::new(env!("CARGO_MANIFEST_DIR")).join("src"),
        &Vec::new(),
        &mut out,
    );
    out
}

/// The paths a module names: `super::a::{B, c::D}` gives `[super, a, B]`
/// and `[super, a, c, D]`; `crate::app::X` gives `[crate, app, X]`.
fn paths(code: &str) -> Vec<Vec<String>> {
    let mut out = Vec::new();
    for start in ["super::", "crate::", "self::"] {
        for (at, _) in code.match_indices(start) {
            // Not the second `super` of `super::super`, nor `x::self::`.
            let boundary = code[..at]
                .chars()
                .next_back()
                .is_none_or(|c| !(c.is_alphanumeric() || c == '_' || c == ':'));
            if boundary {
                expand(&code[at..], Vec::new(), &mut out);
            }
        }
    }
    out
}

/// Reads one path (with `{...}` groups) from the start of `text`.
fn expand(text: &str, prefix: Vec<String>, out: &mut Vec<Vec<String>>) {
    let mut path = prefix;
    let mut rest = text;
    loop {
        let end = rest
            .find(|c: char| !(c.is_alphanumeric() || c == '_'))
            .unwrap_or(rest.len());
        if end > 0 {
            path.push(rest[..end].to_owned());
        }
        rest = &rest[end..];
        if let Some(after) = rest.strip_prefix("::") {
            if let Some(group) = after.strip_prefix('{') {
                for part in split_group(group) {
                    expand(part.trim(), path.clone(), out);
                }
                return;
            }
            rest = after;
        } else {
            out.push(path);
            return;
        }
    }
}

/// The comma-separated parts of a `{...}` group (the text after `{`).
fn split_group(group: &str) -> Vec<&str> {
    let (mut depth, mut from, mut parts) = (0, 0, Vec::new());
    for (i, c) in group.char_indices() {
        match c {
            '{' => depth += 1,
            '}' if depth == 0 => {
                parts.push(&group[from..i]);
                return parts;
            }
            '}' => depth -= 1,
            ',' if depth == 0 => {
                parts.push(&group[from..i]);
                from = i + 1;
            }
            _ => {}
        }
    }
    parts
}

/// What `module` brings in with `use` (private, `pub` or restricted):
/// the item's name (or its `as` name) to the path it comes from (relative
/// to `module`).
fn uses(code: &str) -> BTreeMap<String, Vec<String>> {
    let mut out = BTreeMap::new();
    for statement in code.split(';') {
        // The last `use` of the statement, after attributes, visibility or
        // the end of an earlier item.
        let Some(at) = statement.rmatch_indices("use ").map(|(at, _)| at).find(|&at| {
            statement[..at]
                .chars()
                .next_back()
                .is_none_or(|c| c.is_whitespace() || c == ')' || c == '{' || c == '}')
        }) else {
            continue;
        };
        let body = statement[at + 4..].trim();
        let mut paths = Vec::new();
        expand(body, Vec::new(), &mut paths);
        for path in paths {
            if let Some(last) = path.last() {
                out.insert(last.clone(), path);
            }
        }
        // `use a::B as C`: `C` names `a::B` (one path per statement).
        if let Some((path, alias)) = body.rsplit_once(" as ")
            && !path.contains('{')
        {
            let mut paths = Vec::new();
            expand(path.trim(), Vec::new(), &mut paths);
            if let Some(path) = paths.pop() {
                out.insert(alias.trim().to_owned(), path);
            }
        }
    }
    out
}

/// The module that defines what `path` (named in `from`) names, at module
/// granularity; `None` for paths that leave the engine.
fn resolve(all: &BTreeMap<Module, String>, from: &Module, path: &[String]) -> Option<Module> {
    // `super` of `a/b.rs` and of `a/b/mod.rs` alike is `a`.
    let mut base = from.clone();
    let mut segments = path;
    match segments.first().map(String::as_str) {
        Some("crate") => {
            base = Vec::new();
            segments = &segments[1..];
        }
        Some("self") => segments = &segments[1..],
        _ => {
            while segments.first().map(String::as_str) == Some("super") {
                base.pop()?;
                segments = &segments[1..];
            }
        }
    }
    // Descend through modules while the segments name them.
    let mut depth = 0;
    while let Some(segment) = segments.get(depth) {
        let mut child = base.clone();
        child.push(segment.clone());
        if all.contains_key(&child) {
            base = child;
            depth += 1;
        } else {
            break;
        }
    }
    let rest = &segments[depth..];
    let Some(item) = rest.first() else {
        return Some(base);
    };
    if item == "*" || item == "self" {
        return Some(base);
    }
    // An item of `base`: its own, or brought in by a `use` (from one of
    // its modules, from elsewhere in the engine, or from outside).
    let Some(source) = uses(&all[&base]).get(item).cloned() else {
        return Some(base);
    };
    match source.first().map(String::as_str) {
        Some("crate" | "super" | "self") => resolve(all, &base, &source),
        Some(first) if all.contains_key(&[base.clone(), vec![first.to_owned()]].concat()) => {
            resolve(all, &base, &source)
        }
        // From outside the engine (std, a dependency): `base` re-exports it.
        _ => Some(base),
    }
}

/// Whether `path` is `module` itself or inside it.
fn within(path: &Module, module: &Module) -> bool {
    path.starts_with(module)
}

/// The modules under `folder` (`"a/b"`, `""` for all).
fn split(folder: &str) -> Module {
    folder.split('/').filter(|s| !s.is_empty()).map(str::to_owned).collect()
}

#[test]
fn no_module_imports_one_that_imports_it() {
    let all = modules();
    assert!(all.len() > 80, "the modules of src/: {:?}", all.keys());
    let app = split("app");
    // Every import, as an edge between the modules defining each side.
    let mut edges: BTreeSet<(Module, Module)> = BTreeSet::new();
    let mut found = Vec::new();
    for (module, code) in &all {
        for path in paths(code) {
            let Some(target) = resolve(&all, module, &path) else {
                continue;
            };
            if !within(module, &target) && !within(&target, module) {
                edges.insert((module.clone(), target.clone()));
            }
            // In app/, a child never uses what a folder's mod.rs itself defines.
            let is_folder = all.keys().any(|m| m.len() > target.len() && m.starts_with(&target));
            if within(module, &app)
                && within(&target, &app)
                && is_folder
                && module.len() > target.len()
                && within(module, &target)
            {
                found.push(format!(
                    "{} uses {} defined in the mod.rs of {} that declares it",
                    module.join("/"),
                    path.join("::"),
                    target.join("/")
                ));
            }
        }
    }
    // At each folder, `src/` itself included, the graph of its children
    // (every module folded into the child of that folder it lies in) has no
    // cycle.
    let folders: BTreeSet<Module> = all
        .keys()
        .filter_map(|m| m.split_last().map(|(_, f)| f.to_vec()))
        .collect();
    for folder in folders {
        let fold = |m: &Module| -> Option<String> {
            (m.len() > folder.len() && m.starts_with(&folder)).then(|| m[folder.len()].clone())
        };
        let mut graph: BTreeMap<String, BTreeSet<String>> = BTreeMap::new();
        for (from, to) in &edges {
            if let (Some(a), Some(b)) = (fold(from), fold(to))
                && a != b
            {
                graph.entry(a).or_default().insert(b);
            }
        }
        for group in cycles(&graph) {
            // The imports that make it, module by module.
            let witnesses: Vec<String> = edges
                .iter()
                .filter(|(from, to)| {
                    fold(from).is_some_and(|a| group.contains(&a)) && fold(to).is_some_and(|b| group.contains(&b))
                })
                .filter(|(from, to)| fold(from) != fold(to))
                .map(|(from, to)| format!("{} -> {}", from.join("/"), to.join("/")))
                .collect();
            found.push(format!(
                "a cycle among the modules of src/{}: {} import one another ({})",
                folder.join("/"),
                group.iter().cloned().collect::<Vec<_>>().join(", "),
                witnesses.join(", ")
            ));
        }
    }
    assert!(found.is_empty(), "{}", found.join("\n"));
    // The checker sees the imports it should: a known edge of each kind.
    let edge = |a: &str, b: &str| {
        let (a, b) = (split(a), split(b));
        edges.iter().any(|(from, to)| within(from, &a) && within(to, &b))
    };
    assert!(
        edge("app/session", "app/api/game"),
        "use crate::app::api::game::..: {edges:?}"
    );
    assert!(
        edge("app/net/session", "app/session"),
        "crate::app::GameSession: {edges:?}"
    );
    assert!(
        edge("app/runner/window/surface", "app/runner/window/options"),
        "use super::options::..: {edges:?}"
    );
    assert!(
        edge("app/runner/window/keys", "app/api/control"),
        "crate::app::api::control: {edges:?}"
    );
    assert!(edge("step", "world"), "use crate::world::..: {edges:?}");
    assert!(edge("scene", "forces"), "use crate::forces::..: {edges:?}");
    assert!(
        edge("headless", "clock/rate"),
        "crate::clock::Rate, re-exported: {edges:?}"
    );
    assert!(
        edge("input/recording", "platform"),
        "crate::platform::write_text: {edges:?}"
    );
}

/// Each optional feature's crates are named only in its own folder of
/// `app/` (or the one module of `render/` or `platform/` that needs them),
/// so a feature is one `#[cfg]` on one `mod` line, and a reader finds the
/// netcode, the sound or the window in one place.
#[test]
fn each_features_crates_stay_in_its_folder() {
    let rules: [(&str, &str, &[&str]); 12] = [
        ("tiled", "tiled::", &["tilemap/read"]),
        ("tiled", "quick_xml::", &["tilemap/read"]),
        ("netcode", "ggrs::", &["app/net"]),
        ("netcode", "bincode::", &["app/net"]),
        ("audio", "kira::", &["app/audio"]),
        ("cli", "clap::", &["app/runner/options"]),
        ("window", "winit::", &["app/runner/window", "platform"]),
        ("gamepad", "gilrs::", &["app/runner/window/gamepads"]),
        (
            "text",
            "glyphon::",
            &["render/hud", "render/text_layout", "render/overlay"],
        ),
        ("panel", "egui_plot::", &["app/panel"]),
        ("panel", "egui_wgpu::", &["app/runner/window/panel"]),
        ("panel", "egui_winit::", &["app/runner/window/panel"]),
    ];
    let all = modules();
    let mut found = Vec::new();
    let mut seen = BTreeSet::new();
    for (module, code) in &all {
        for (feature, prefix, allowed) in rules {
            let named = code.match_indices(prefix).any(|(at, _)| {
                code[..at]
                    .chars()
                    .next_back()
                    .is_none_or(|c| !(c.is_alphanumeric() || c == '_' || c == ':'))
            });
            if !named {
                continue;
            }
            seen.insert(prefix);
            if !allowed.iter().any(|a| within(module, &split(a))) {
                found.push(format!(
                    "src/{} names {prefix} (the `{feature}` feature's), which only {} may",
                    module.join("/"),
                    allowed.join(", ")
                ));
            }
        }
    }
    assert!(found.is_empty(), "{}", found.join("\n"));
    // The check sees each crate where it is used.
    assert_eq!(seen.len(), rules.len(), "crates named somewhere: {seen:?}");
}

/// The groups of `graph`'s nodes that reach one another (its strongly
/// connected components of more than one node): each holds a cycle.
fn cycles(graph: &BTreeMap<String, BTreeSet<String>>) -> Vec<BTreeSet<String>> {
    let reach = |from: &String| -> BTreeSet<String> {
        let mut seen = BTreeSet::new();
        let mut stack = vec![from.clone()];
        while let Some(node) = stack.pop() {
            for next in graph.get(&node).into_iter().flatten() {
                if seen.insert(next.clone()) {
                    stack.push(next.clone());
                }
            }
        }
        seen
    };
    let reached: BTreeMap<&String, BTreeSet<String>> = graph.keys().map(|n| (n, reach(n))).collect();
    let mut groups: Vec<BTreeSet<String>> = Vec::new();
    for (node, from_node) in &reached {
        if !from_node.contains(*node) || groups.iter().any(|g| g.contains(*node)) {
            continue;
        }
        let group: BTreeSet<String> = from_node
            .iter()
            .filter(|other| reached.get(other).is_some_and(|r| r.contains(*node)))
            .cloned()
            .collect();
        groups.push(group);
    }
    groups
}

/// The CPU/GPU boundary has one owner each way: the GPU step reads no
/// force's or collider's type (each says its GPU form, `gpu_form`), and
/// the runners read a world's backend in one place (`app/api/backend.rs`,
/// `on_gpu`), besides the world itself and the settings that set it.
#[test]
fn the_gpu_step_reads_no_types_and_one_module_reads_the_backend() {
    let all = modules();
    let gpu_step = split("gpu_step");
    let downcasts: Vec<String> = all
        .iter()
        .filter(|(module, code)| within(module, &gpu_step) && (code.contains("downcast") || code.contains("as_any(")))
        .map(|(module, _)| module.join("/"))
        .collect();
    assert!(downcasts.is_empty(), "gpu_step reads a type: {downcasts:?}");
    let reads: Vec<String> = all
        .iter()
        .filter(|(_, code)| code.contains("config().backend") || code.contains("config.backend"))
        .map(|(module, _)| module.join("/"))
        .collect();
    assert_eq!(
        reads,
        ["app/api/backend", "app/api/stage", "world/world"],
        "the modules that read or set WorldConfig::backend"
    );
    // The checker sees the one read it allows.
    assert!(all[&split("app/api/backend")].contains("config().backend == Backend::Gpu"));
}
