//! The modules of `engine/src/app` import one another without a cycle, as
//! ARCHITECTURE.md says: read from the source, every `super::` and
//! `crate::app::` path is resolved to the module that defines what it
//! names (through the re-exports of a `mod.rs`), and the graph that makes
//! is checked for cycles, at each level of folders.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

/// A module's path below `app`, as folders: `[]` is `app` itself,
/// `["window", "surface"]` is `app/window/surface.rs`.
type Module = Vec<String>;

/// Every module of `app/` with its source (up to its tests).
fn modules() -> BTreeMap<Module, String> {
    fn walk(dir: &Path, prefix: &Module, out: &mut BTreeMap<Module, String>) {
        let mut entries: Vec<PathBuf> = std::fs::read_dir(dir)
            .expect("app/ is readable")
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
                let mut module = prefix.clone();
                if name != "mod" {
                    module.push(name);
                }
                let text = std::fs::read_to_string(&path).expect("readable source");
                // A `mod tests` says `super::` of its own file: not an import.
                let code = text.split("#[cfg(test)]").next().unwrap_or_default();
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
        &Path::new(env!("CARGO_MANIFEST_DIR")).join("src/app"),
        &Vec::new(),
        &mut out,
    );
    out
}

/// The paths a module names: `super::a::{B, c::D}` gives `[super, a, B]`
/// and `[super, a, c, D]`; `crate::app::X` gives `[crate, app, X]`.
fn paths(code: &str) -> Vec<Vec<String>> {
    let mut out = Vec::new();
    for start in ["super::", "crate::app::"] {
        for (at, _) in code.match_indices(start) {
            // Not the second `super` of `super::super`, nor `x::crate::`.
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

/// What `module` re-exports with `pub use`/`use`: the item's name to the
/// path it comes from (relative to `module`).
fn uses(code: &str) -> BTreeMap<String, Vec<String>> {
    let mut out = BTreeMap::new();
    for statement in code.split(';') {
        let statement = statement.trim();
        let Some(body) = statement
            .strip_prefix("pub use ")
            .or_else(|| statement.strip_prefix("use "))
            .or_else(|| statement.strip_prefix("pub(super) use "))
        else {
            continue;
        };
        let mut paths = Vec::new();
        expand(body.trim(), Vec::new(), &mut paths);
        for path in paths {
            if let Some(last) = path.last() {
                out.insert(last.clone(), path);
            }
        }
    }
    out
}

/// The module that defines what `path` (named in `from`) names, at module
/// granularity; `None` for paths that leave `app`.
fn resolve(all: &BTreeMap<Module, String>, from: &Module, path: &[String]) -> Option<Module> {
    // `super` of `app/a.rs` and of `app/a/mod.rs` alike is `app`.
    let mut base = from.clone();
    let mut segments = path;
    if segments.first().map(String::as_str) == Some("crate") {
        base = Vec::new();
        segments = &segments[2..];
    } else {
        while segments.first().map(String::as_str) == Some("super") {
            base.pop()?;
            segments = &segments[1..];
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
    // its modules, from elsewhere in `app`, or from outside).
    let Some(source) = uses(&all[&base]).get(item).cloned() else {
        return Some(base);
    };
    match source.first().map(String::as_str) {
        Some("crate") if source.get(1).map(String::as_str) == Some("app") => resolve(all, &base, &source),
        Some("super") => resolve(all, &base, &source),
        Some(first) if all.contains_key(&[base.clone(), vec![first.to_owned()]].concat()) => {
            resolve(all, &base, &source)
        }
        // Outside `app` (another engine module, std, a dependency).
        _ => None,
    }
}

/// Whether `path` is `module` itself or inside it.
fn within(path: &Module, module: &Module) -> bool {
    path.starts_with(module)
}

#[test]
fn no_module_of_app_imports_one_that_imports_it() {
    let all = modules();
    assert!(all.len() > 20, "the modules of app/: {:?}", all.keys());
    // Every import, as an edge between the modules defining each side.
    let mut edges: BTreeSet<(Module, Module)> = BTreeSet::new();
    for (module, code) in &all {
        for path in paths(code) {
            if let Some(target) = resolve(&all, module, &path)
                && !within(module, &target)
                && !within(&target, module)
            {
                edges.insert((module.clone(), target));
            }
        }
        // A child never uses what a folder's mod.rs itself defines.
        for path in paths(code) {
            if let Some(target) = resolve(&all, module, &path) {
                let is_folder = all.keys().any(|m| m.len() > target.len() && m.starts_with(&target));
                assert!(
                    !(is_folder && module.len() > target.len() && within(module, &target)),
                    "app/{} uses {} defined in the mod.rs of app/{} that declares it",
                    module.join("/"),
                    path.join("::"),
                    target.join("/")
                );
            }
        }
    }
    // At each folder, the graph of its children (every module folded into
    // the child of that folder it lies in) has no cycle.
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
        if let Some(cycle) = find_cycle(&graph) {
            panic!(
                "a cycle among the modules of app/{}: {}",
                folder.join("/"),
                cycle.join(" -> ")
            );
        }
    }
    // The checker sees the imports it should: a known edge of each kind.
    let edge = |a: &str, b: &str| {
        let split = |s: &str| -> Module { s.split('/').filter(|s| !s.is_empty()).map(str::to_owned).collect() };
        edges.contains(&(split(a), split(b)))
    };
    assert!(edge("session", "game"), "use super::game::..: {edges:?}");
    assert!(edge("network/session", "session"), "crate::app::GameSession: {edges:?}");
    assert!(
        edge("window/surface", "window/options"),
        "use super::options::..: {edges:?}"
    );
    assert!(edge("window/keys", "control"), "super::super::control: {edges:?}");
}

/// A cycle in `graph`, as the modules along it, if there is one.
fn find_cycle(graph: &BTreeMap<String, BTreeSet<String>>) -> Option<Vec<String>> {
    fn visit(
        node: &String,
        graph: &BTreeMap<String, BTreeSet<String>>,
        stack: &mut Vec<String>,
        done: &mut BTreeSet<String>,
    ) -> Option<Vec<String>> {
        if let Some(at) = stack.iter().position(|n| n == node) {
            let mut cycle = stack[at..].to_vec();
            cycle.push(node.clone());
            return Some(cycle);
        }
        if done.contains(node) {
            return None;
        }
        stack.push(node.clone());
        for next in graph.get(node).into_iter().flatten() {
            if let Some(cycle) = visit(next, graph, stack, done) {
                return Some(cycle);
            }
        }
        stack.pop();
        done.insert(node.clone());
        None
    }
    let mut done = BTreeSet::new();
    graph
        .keys()
        .find_map(|node| visit(node, graph, &mut Vec::new(), &mut done))
}
