//! The front door keeps its word: every `kisstime` command in a ```sh block of README.md and
//! python/README.md runs as written (from a folder holding the repository's `examples/` and
//! `data/`, as a clone does) and exits 0, and where a ```text block follows it, that block is
//! its output (standard output, then standard error; a line `…` stands for any lines, a
//! line ending in `…` for any line that starts with what precedes it). Every relative link
//! of README.md, python/README.md and docs/*.md reaches a file, and every `#anchor` a
//! heading of it. (The Python examples: python/tests/test_readme.py.)

use std::path::{Path, PathBuf};
use std::process::Command;

const ROOT: &str = env!("CARGO_MANIFEST_DIR");

/// A fenced block: its language and its lines; `follows` when only blank lines separate it
/// from the block before.
struct Block {
    lang: String,
    lines: Vec<String>,
    follows: bool,
}

fn blocks(text: &str) -> Vec<Block> {
    let mut out: Vec<Block> = Vec::new();
    let mut current: Option<Block> = None;
    let mut gap_is_blank = false;
    for line in text.lines() {
        match current.take() {
            Some(mut b) => {
                if line.trim_start().starts_with("```") {
                    out.push(b);
                    gap_is_blank = true;
                } else {
                    b.lines.push(line.to_owned());
                    current = Some(b);
                }
            }
            None => {
                if let Some(lang) = line.trim_start().strip_prefix("```") {
                    current = Some(Block {
                        lang: lang.trim().to_owned(),
                        lines: Vec::new(),
                        follows: gap_is_blank && !out.is_empty(),
                    });
                } else if !line.trim().is_empty() {
                    gap_is_blank = false;
                }
            }
        }
    }
    assert!(current.is_none(), "an unclosed code block");
    out
}

/// The `kisstime` commands of a shell block, as argument lists (continuations joined,
/// comments dropped, `cargo run --release --` read as `kisstime`).
fn commands(block: &Block) -> Vec<Vec<String>> {
    let mut joined = Vec::new();
    let mut acc = String::new();
    for line in &block.lines {
        let line = match line.find(" #") {
            Some(k) => &line[..k],
            None => line.as_str(),
        };
        if let Some(head) = line.trim_end().strip_suffix('\\') {
            acc += head;
            acc.push(' ');
        } else {
            acc += line;
            joined.push(std::mem::take(&mut acc));
        }
    }
    joined
        .iter()
        .filter_map(|l| {
            let l = l.trim();
            let rest = l
                .strip_prefix("kisstime ")
                .or_else(|| l.strip_prefix("cargo run --release -- "))?;
            assert!(
                !rest.contains(['"', '\'', '|', '>', '<', '$', '`']),
                "the runner takes plain words only: {l}"
            );
            Some(rest.split_whitespace().map(str::to_owned).collect())
        })
        .collect()
}

/// Whether `actual` is what `shown` shows (`…` lines and `…` endings as the module says).
fn shows(shown: &[String], actual: &[&str]) -> Result<(), String> {
    fn line_ok(e: &str, a: &str) -> bool {
        match e.strip_suffix('…') {
            Some(prefix) => a.trim_end().starts_with(prefix),
            None => e.trim_end() == a.trim_end(),
        }
    }
    let (mut i, mut j) = (0, 0);
    while i < shown.len() {
        if shown[i].trim() == "…" {
            i += 1;
            if i == shown.len() {
                return Ok(());
            }
            while j < actual.len() && !line_ok(&shown[i], actual[j]) {
                j += 1;
            }
            if j == actual.len() {
                return Err(format!("no line shows {:?}", shown[i]));
            }
        }
        match actual.get(j) {
            Some(a) if line_ok(&shown[i], a) => {}
            other => {
                return Err(format!(
                    "shown line {} {:?}, got {:?}",
                    i + 1,
                    shown[i],
                    other
                ));
            }
        }
        i += 1;
        j += 1;
    }
    if j < actual.len() {
        return Err(format!("more output than shown, from {:?}", actual[j]));
    }
    Ok(())
}

/// A folder that looks like a clone to the examples: `examples/` and `data/` linked in.
fn workdir() -> tempfile::TempDir {
    let dir = tempfile::tempdir().unwrap();
    for sub in ["examples", "data"] {
        std::os::unix::fs::symlink(Path::new(ROOT).join(sub), dir.path().join(sub)).unwrap();
    }
    dir
}

fn run_examples(file: &str) -> usize {
    let text = std::fs::read_to_string(Path::new(ROOT).join(file)).unwrap();
    let blocks = blocks(&text);
    let dir = workdir();
    let mut ran = 0;
    for (k, block) in blocks.iter().enumerate() {
        if block.lang != "sh" {
            continue;
        }
        let cmds = commands(block);
        for (c, args) in cmds.iter().enumerate() {
            let out = Command::new(env!("CARGO_BIN_EXE_kisstime"))
                .args(args)
                .current_dir(dir.path())
                .output()
                .expect("the kisstime binary runs");
            let stdout = String::from_utf8_lossy(&out.stdout).into_owned();
            let stderr = String::from_utf8_lossy(&out.stderr).into_owned();
            assert!(
                out.status.success(),
                "{file}: `kisstime {}` failed: {stderr}",
                args.join(" ")
            );
            ran += 1;
            let last = c + 1 == cmds.len();
            if let Some(next) = blocks.get(k + 1)
                && last
                && next.follows
                && next.lang == "text"
            {
                let actual: Vec<&str> = stdout.lines().chain(stderr.lines()).collect();
                if let Err(e) = shows(&next.lines, &actual) {
                    panic!(
                        "{file}: the output shown under `kisstime {}` is not its output: \
                         {e}\n--- output:\n{stdout}{stderr}",
                        args.join(" ")
                    );
                }
            }
        }
    }
    ran
}

#[test]
fn the_readme_commands_run_as_written_and_print_what_is_shown() {
    let ran = run_examples("README.md");
    assert!(ran >= 4, "the README shows {ran} commands");
    run_examples("python/README.md");
}

#[test]
fn the_output_matcher_can_fail() {
    let shown: Vec<String> = ["a", "…", "c…"].iter().map(|s| s.to_string()).collect();
    assert!(shows(&shown, &["a", "x", "y", "c 1 s"]).is_ok());
    assert!(shows(&shown, &["a", "x"]).is_err());
    assert!(shows(&shown, &["b", "c"]).is_err());
    let exact: Vec<String> = vec!["a".into()];
    assert!(shows(&exact, &["a", "b"]).is_err());
}

/// GitHub's anchor of a heading: lower case, spaces to `-`, other punctuation dropped.
fn slug(heading: &str) -> String {
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

fn anchors(text: &str) -> Vec<String> {
    let mut out = Vec::new();
    let mut fenced = false;
    for line in text.lines() {
        if line.trim_start().starts_with("```") {
            fenced = !fenced;
        }
        if fenced {
            continue;
        }
        if line.starts_with('#') {
            out.push(slug(line.trim_start_matches('#')));
        }
        let mut rest = line;
        while let Some(k) = rest.find("<a id=\"") {
            let tail = &rest[k + 7..];
            let end = tail.find('"').unwrap_or(tail.len());
            out.push(tail[..end].to_owned());
            rest = &tail[end..];
        }
    }
    out
}

#[test]
fn every_relative_link_of_the_docs_reaches_its_file_and_heading() {
    let mut files: Vec<PathBuf> = vec![
        Path::new(ROOT).join("README.md"),
        Path::new(ROOT).join("python/README.md"),
    ];
    for e in std::fs::read_dir(Path::new(ROOT).join("docs")).unwrap() {
        let p = e.unwrap().path();
        if p.extension().is_some_and(|x| x == "md") {
            files.push(p);
        }
    }
    let mut checked = 0;
    for file in &files {
        let text = std::fs::read_to_string(file).unwrap();
        let mut rest = text.as_str();
        while let Some(k) = rest.find("](") {
            let tail = &rest[k + 2..];
            let end = tail.find(')').unwrap_or(tail.len());
            let target = &tail[..end];
            rest = &tail[end..];
            if target.starts_with("http") || target.contains(' ') {
                continue;
            }
            let (path, anchor) = target.split_once('#').unwrap_or((target, ""));
            let dest = if path.is_empty() {
                file.clone()
            } else {
                file.parent().unwrap().join(path)
            };
            assert!(
                dest.exists(),
                "{}: the link {target} reaches nothing",
                file.display()
            );
            if !anchor.is_empty() {
                let text = std::fs::read_to_string(&dest).unwrap();
                assert!(
                    anchors(&text).iter().any(|a| a == anchor),
                    "{}: the link {target}: no such heading in {}",
                    file.display(),
                    dest.display()
                );
            }
            checked += 1;
        }
    }
    assert!(checked > 20, "only {checked} links found");
}

#[test]
fn the_readme_stays_a_front_door() {
    let text = std::fs::read_to_string(Path::new(ROOT).join("README.md")).unwrap();
    let lines = text.lines().count();
    assert!(
        lines <= 260,
        "README.md has {lines} lines: keep it near 250"
    );
}
