//! The GPU event loop's storage layout is one layout: for every ball-count bucket, every
//! layout constant the host uses (`kisstime::gpu::SimLayout::named`) is declared in the
//! shader with the same name, and its declaration, evaluated with the shader's
//! `GPU_MAX_BALLS` set to the bucket (as the host builds it), gives the host's value; and
//! the shader indexes its storage only through named constants.

use std::collections::HashMap;

/// `const NAME: u32 = EXPR;` declarations of a WGSL source, as (name, expression).
fn u32_consts(source: &str) -> Vec<(String, String)> {
    let mut out = Vec::new();
    for line in source.lines() {
        let Some(rest) = line.trim().strip_prefix("const ") else {
            continue;
        };
        let Some((name, value)) = rest.split_once(": u32 = ") else {
            continue;
        };
        out.push((name.to_owned(), value.trim_end_matches(';').to_owned()));
    }
    out
}

/// The value of a WGSL u32 constant expression of `+ - * /`, parentheses, literals
/// (`12u`, `0xffu`) and names already known.
fn eval(expr: &str, env: &HashMap<String, u64>) -> u64 {
    fn tokens(expr: &str) -> Vec<String> {
        let mut out = Vec::new();
        let mut word = String::new();
        for c in expr.chars() {
            if c.is_ascii_alphanumeric() || c == '_' {
                word.push(c);
            } else {
                if !word.is_empty() {
                    out.push(std::mem::take(&mut word));
                }
                if !c.is_whitespace() {
                    out.push(c.to_string());
                }
            }
        }
        if !word.is_empty() {
            out.push(word);
        }
        out
    }
    fn sum(t: &[String], at: &mut usize, env: &HashMap<String, u64>) -> u64 {
        let mut v = product(t, at, env);
        while *at < t.len() && (t[*at] == "+" || t[*at] == "-") {
            let op = t[*at].clone();
            *at += 1;
            let w = product(t, at, env);
            v = if op == "+" { v + w } else { v - w };
        }
        v
    }
    fn product(t: &[String], at: &mut usize, env: &HashMap<String, u64>) -> u64 {
        let mut v = atom(t, at, env);
        while *at < t.len() && (t[*at] == "*" || t[*at] == "/") {
            let op = t[*at].clone();
            *at += 1;
            let w = atom(t, at, env);
            v = if op == "*" { v * w } else { v / w };
        }
        v
    }
    fn atom(t: &[String], at: &mut usize, env: &HashMap<String, u64>) -> u64 {
        let tok = t[*at].clone();
        *at += 1;
        if tok == "(" {
            let v = sum(t, at, env);
            assert_eq!(t[*at], ")");
            *at += 1;
            return v;
        }
        let lit = tok.trim_end_matches('u');
        if let Some(hex) = lit.strip_prefix("0x") {
            return u64::from_str_radix(hex, 16).unwrap();
        }
        if let Ok(v) = lit.parse() {
            return v;
        }
        *env.get(&tok)
            .unwrap_or_else(|| panic!("{tok}: not declared before it is used"))
    }
    let t = tokens(expr);
    let mut at = 0;
    let v = sum(&t, &mut at, env);
    assert_eq!(
        at,
        t.len(),
        "{expr}: not a constant expression this test reads"
    );
    v
}

fn shader(path: &str) -> String {
    std::fs::read_to_string(format!("{}/shaders/{path}", env!("CARGO_MANIFEST_DIR"))).unwrap()
}

#[test]
fn every_host_layout_constant_is_the_shaders_in_every_bucket() {
    let mut decls = u32_consts(&shader("simulate/cache.wgsl"));
    decls.extend(u32_consts(&shader("simulate/event_loop.wgsl")));
    assert!(
        shader("simulate/cache.wgsl").contains(kisstime::gpu::GPU_MAX_BALLS_LINE),
        "the line the host rewrites is in cache.wgsl"
    );
    assert!(
        shader("simulate/event_loop.wgsl").contains(kisstime::gpu::shader::TABLES_PER_GROUP_LINE),
        "the line the host rewrites is in event_loop.wgsl"
    );
    assert_eq!(kisstime::gpu::GPU_BALL_BUCKETS, [16, 32, 48, 64]);
    for bucket in kisstime::gpu::GPU_BALL_BUCKETS {
        let mut env = HashMap::new();
        for (name, expr) in &decls {
            let v = if name == "GPU_MAX_BALLS" {
                bucket as u64
            } else {
                eval(expr, &env)
            };
            env.insert(name.clone(), v);
        }
        let layout = kisstime::gpu::SimLayout::for_balls(bucket);
        let named = layout.named();
        assert!(named.len() >= 20);
        for (name, value) in named {
            assert_eq!(
                env.get(name).copied(),
                Some(value as u64),
                "{name} for {bucket} balls: the shader's value differs from the host's {value}"
            );
        }
    }
    // the buckets: the smallest that holds a table
    let bucket = |n| kisstime::gpu::SimLayout::bucket(n).map(|l| l.gpu_max_balls);
    assert_eq!(bucket(2), Some(16));
    assert_eq!(bucket(16), Some(16));
    assert_eq!(bucket(22), Some(32));
    assert_eq!(bucket(40), Some(48));
    assert_eq!(bucket(64), Some(64));
    assert_eq!(bucket(65), None);
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
