//! The library's module graph points one way (issue 15, ARCHITECTURE.md): every top-level
//! module of `src/` uses only modules below it in [`LAYERS`]. Read from the source text: each
//! `crate::NAME` outside comments and tests is a use of `NAME`.

use std::collections::BTreeSet;
use std::path::{Path, PathBuf};

/// The top-level modules, bottom first: the shared base, reading, the pipeline stages of §3–§5
/// and the interpolation of §4, the artwork and its frames, automatic mode, the exporters, the
/// front door. A module may use the ones before it, never one after it.
const LAYERS: &[&str] = &[
    "error",
    "geometry",
    "grid",
    "tolerance",
    "base64",
    "number",
    "parallel",
    "mesh",
    "input",
    "budget",
    "drawing",
    "correspondence",
    "artwork",
    "color",
    "rigid",
    "quality",
    "triangulation",
    "mapping",
    "compatible",
    "json",
    "inspect",
    "skeleton",
    "morphing",
    "frame",
    "render",
    "auto",
    "export",
    "morpher",
];

/// The `.rs` files of top-level module `name` (its file and its folder), tests left out.
fn files_of(src: &Path, name: &str) -> Vec<PathBuf> {
    let mut out = Vec::new();
    let file = src.join(format!("{name}.rs"));
    if file.is_file() {
        out.push(file);
    }
    let mut dirs = vec![src.join(name)];
    while let Some(dir) = dirs.pop() {
        let Ok(entries) = std::fs::read_dir(&dir) else {
            continue;
        };
        for e in entries.flatten() {
            let p = e.path();
            if p.is_dir() {
                dirs.push(p);
            } else if p.extension().is_some_and(|x| x == "rs")
                && p.file_name().is_some_and(|n| n != "tests.rs")
            {
                out.push(p);
            }
        }
    }
    out
}

/// `text` without its `#[cfg(test)]` items: an item that ends on its first line
/// (`mod tests;`), or one whose braces close further down (`mod tests { … }`).
fn without_tests(text: &str) -> String {
    let mut out = String::new();
    let mut lines = text.lines();
    while let Some(line) = lines.next() {
        if line.trim_start().starts_with("#[cfg(test)]") {
            // Skip the item: up to the line that ends it, counting braces.
            let mut depth = 0i64;
            let mut opened = false;
            for item in lines.by_ref() {
                depth += item.matches('{').count() as i64 - item.matches('}').count() as i64;
                opened |= item.contains('{');
                if (opened && depth <= 0) || (!opened && item.trim_end().ends_with(';')) {
                    break;
                }
            }
            continue;
        }
        out.push_str(line);
        out.push('\n');
    }
    out
}

/// The modules `text` uses (`crate::NAME`), comments and its `#[cfg(test)]` items left out.
fn uses(text: &str) -> BTreeSet<String> {
    let code = without_tests(text);
    let mut out = BTreeSet::new();
    for line in code.lines().filter(|l| !l.trim_start().starts_with("//")) {
        for (i, _) in line.match_indices("crate::") {
            let name: String = line[i + "crate::".len()..]
                .chars()
                .take_while(|c| c.is_ascii_lowercase() || c.is_ascii_digit() || *c == '_')
                .collect();
            out.insert(name);
        }
    }
    out
}

#[test]
fn every_module_uses_only_modules_below_it() {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut modules: Vec<String> = std::fs::read_dir(&src)
        .unwrap()
        .flatten()
        .filter_map(|e| {
            let p = e.path();
            let stem = p.file_stem()?.to_str()?.to_string();
            (stem != "lib" && (p.is_dir() || p.extension().is_some_and(|x| x == "rs")))
                .then_some(stem)
        })
        .collect();
    modules.sort();
    modules.dedup();
    let placed: BTreeSet<&str> = LAYERS.iter().copied().collect();
    let unplaced: Vec<&String> = modules
        .iter()
        .filter(|m| !placed.contains(m.as_str()))
        .collect();
    assert!(
        unplaced.is_empty(),
        "modules missing from LAYERS: {unplaced:?}"
    );
    let mut upward = Vec::new();
    for (level, name) in LAYERS.iter().enumerate() {
        let files = files_of(&src, name);
        assert!(
            !files.is_empty(),
            "LAYERS names '{name}', which src/ does not have"
        );
        for f in files {
            let text = std::fs::read_to_string(&f).unwrap();
            for used in uses(&text) {
                let at = LAYERS.iter().position(|m| *m == used);
                if at.is_some_and(|at| at > level) {
                    upward.push(format!("{} uses {used}", f.display()));
                }
            }
        }
    }
    assert!(upward.is_empty(), "uses of modules above: {upward:#?}");
}

#[test]
fn a_use_is_found_and_comments_and_tests_are_not() {
    let text = "use crate::mesh::Side;\n/// [`crate::export::Morph`]\nfn f() { crate::render::fixed(1.0, 2); }\n#[cfg(test)]\nmod tests { use crate::morpher::Morpher; }";
    let found: Vec<String> = uses(text).into_iter().collect();
    assert_eq!(found, ["mesh", "render"]);
}

#[test]
fn code_after_a_test_module_declared_early_is_read() {
    // `#[cfg(test)] mod tests;` near the top hides nothing below it; a test module's body is
    // left out wherever it stands.
    let text = "#[cfg(test)]\nmod tests;\nuse crate::drawing::Controls;\n#[cfg(test)]\nmod more {\n    use crate::auto::X;\n    fn f() { if true { crate::export::g(); } }\n}\nfn h() { crate::rigid::k(); }\n";
    let found: Vec<String> = uses(text).into_iter().collect();
    assert_eq!(found, ["drawing", "rigid"]);
}
