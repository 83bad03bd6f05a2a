//! The GPU event loop's storage layout is one layout: every layout constant the host uses
//! (`kisstime::gpu::SHADER_LAYOUT`) is declared in the shader with the same name and value,
//! and the shader indexes its storage only through named constants.

use std::collections::HashMap;

/// `const NAME: u32 = VALUEu;` declarations of a WGSL source.
fn u32_consts(source: &str) -> HashMap<String, usize> {
    let mut out = HashMap::new();
    for line in source.lines() {
        let Some(rest) = line.trim().strip_prefix("const ") else {
            continue;
        };
        let Some((name, value)) = rest.split_once(": u32 = ") else {
            continue;
        };
        let value = value.trim_end_matches(';').trim_end_matches('u');
        if let Ok(v) = value.parse() {
            out.insert(name.to_owned(), v);
        }
    }
    out
}

fn shader(path: &str) -> String {
    std::fs::read_to_string(format!("{}/shaders/{path}", env!("CARGO_MANIFEST_DIR"))).unwrap()
}

#[test]
fn every_host_layout_constant_is_the_shaders() {
    let mut consts = u32_consts(&shader("simulate/cache.wgsl"));
    consts.extend(u32_consts(&shader("simulate/event_loop.wgsl")));
    assert!(kisstime::gpu::SHADER_LAYOUT.len() >= 20);
    for (name, value) in kisstime::gpu::SHADER_LAYOUT {
        assert_eq!(
            consts.get(*name),
            Some(value),
            "{name}: the shader's value differs from the host's {value}"
        );
    }
}

#[test]
fn the_event_loop_indexes_storage_through_named_constants() {
    let source = shader("simulate/event_loop.wgsl");
    for (k, line) in source.lines().enumerate() {
        let code = line.split("//").next().unwrap();
        if !(code.contains("state_r[") || code.contains("state_u[")) {
            continue;
        }
        // an offset in a storage index is a name (IO_R_TRANS, WATCH_U_FIRST, ...) or a
        // small step within a named block (at + 3u), never a bare position such as 160u
        for word in code.split(|c: char| !c.is_ascii_alphanumeric()) {
            if let Some(n) = word.strip_suffix('u').and_then(|w| w.parse::<u32>().ok()) {
                assert!(
                    n <= 9,
                    "line {}: bare offset {word} in {}",
                    k + 1,
                    line.trim()
                );
            }
        }
    }
}
