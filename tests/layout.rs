//! The library's imports point one way, from the vocabulary up to the drivers: each
//! top-level module of `src/` uses only modules below it in [`LAYERS`], so no module imports
//! one that imports it back. The command line (`src/main.rs`, `src/cli/`) sits on top and
//! is not part of the library. Test modules (`#[cfg(test)] mod tests`) may use anything.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// The library's top-level modules, lowest first. `engine` chooses the backend for the
/// kernels and for whole shots; the study is its client (it runs through
/// `ShotEngine::simulate_with`), so it sits above it, and the planner above the study.
const LAYERS: &[&str] = &[
    "error", "model", "motion", "query", "resolve", "limits", "simulate", "game", "batch", "cpu",
    "gpu", "compare", "io", "workload", "engine", "study", "plan", "env",
];

/// Every `.rs` file under `dir`.
fn rust_files(dir: &Path, out: &mut Vec<PathBuf>) {
    for entry in std::fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        if path.is_dir() {
            rust_files(&path, out);
        } else if path.extension().is_some_and(|e| e == "rs") {
            out.push(path);
        }
    }
}

/// The top-level modules that `text` refers to as `crate::name`, outside comments and its
/// test module.
fn crate_refs(text: &str) -> Vec<String> {
    let code = text.split("#[cfg(test)]\nmod tests").next().unwrap_or(text);
    let mut refs = Vec::new();
    for line in code.lines() {
        let line = line.split("//").next().unwrap_or("");
        let mut rest = line;
        while let Some(at) = rest.find("crate::") {
            rest = &rest[at + "crate::".len()..];
            let end = rest
                .find(|c: char| !(c.is_alphanumeric() || c == '_'))
                .unwrap_or(rest.len());
            refs.push(rest[..end].to_owned());
        }
    }
    refs
}

#[test]
fn library_imports_point_one_way() {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut files = Vec::new();
    rust_files(&src, &mut files);
    let mut uses: BTreeMap<String, Vec<(String, String)>> = BTreeMap::new();
    for file in files {
        let rel = file
            .strip_prefix(&src)
            .unwrap()
            .to_string_lossy()
            .replace('\\', "/");
        if rel == "main.rs" || rel.starts_with("cli/") || rel == "lib.rs" {
            continue;
        }
        let top = rel
            .split('/')
            .next()
            .unwrap()
            .trim_end_matches(".rs")
            .to_owned();
        let text = std::fs::read_to_string(&file).unwrap();
        for r in crate_refs(&text) {
            uses.entry(top.clone()).or_default().push((r, rel.clone()));
        }
    }
    let rank = |m: &str| LAYERS.iter().position(|l| *l == m);
    let mut wrong = Vec::new();
    for (module, refs) in &uses {
        let Some(own) = rank(module) else {
            wrong.push(format!(
                "src/{module}: not in LAYERS (add it where it belongs)"
            ));
            continue;
        };
        for (r, file) in refs {
            match rank(r) {
                // crate-root re-exports (`crate::Error`, …) are items, not modules
                None if r.chars().next().is_some_and(|c| c.is_uppercase()) => {}
                None => wrong.push(format!("src/{file} uses crate::{r}, not a known module")),
                Some(other) if other > own => wrong.push(format!(
                    "src/{file} ({module}) uses crate::{r}, which sits above it"
                )),
                Some(_) => {}
            }
        }
    }
    assert!(wrong.is_empty(), "{}", wrong.join("\n"));
}

#[test]
fn the_reference_scan_sees_paths_and_skips_comments_and_tests() {
    let text = "use crate::model::Ball;\nlet x = crate::limits::check(); // crate::gpu\n#[cfg(test)]\nmod tests {\n    use crate::study::X;\n}\n";
    assert_eq!(crate_refs(text), ["model", "limits"]);
}
