//! The physics parameter readers (`io::physics`: a physics file's TOML,
//! `parse_physics_toml`; a program's mapping, `parse_physics_mapping` and
//! `parse_physics_json`; a per-table physics CSV, `parse_physics_csv` and its
//! `PhysicsColumns::for_tables`) on arbitrary bytes (lossily as UTF-8), the first byte
//! choosing the reader: never panics; an error whose message formats, or parameters that
//! pass `SimParams::validate` (per table for the CSV).
#![no_main]
use libfuzzer_sys::fuzz_target;

use kisstime::io::physics::{
    parse_physics_csv, parse_physics_json, parse_physics_mapping, parse_physics_toml,
};
use kisstime::simulate::SimParams;

fuzz_target!(|data: &[u8]| {
    let Some((&choice, rest)) = data.split_first() else {
        return;
    };
    let text = String::from_utf8_lossy(rest);
    let check = |r: Result<SimParams, kisstime::Error>| match r {
        Ok(p) => p.validate().expect("validated parameters"),
        Err(e) => assert!(!e.to_string().is_empty()),
    };
    match choice % 4 {
        0 => check(parse_physics_toml(&text, "fuzz.toml")),
        1 => check(parse_physics_mapping(&text, "fuzz")),
        2 => check(parse_physics_json(&text, "fuzz")),
        _ => match parse_physics_csv(&text, "fuzz.csv") {
            Err(e) => assert!(!e.to_string().is_empty()),
            Ok(cols) => {
                assert_eq!(cols.tables.len(), cols.lines.len());
                // the tables' parameters, each checked as a physics file's
                match cols.for_tables(&[], &cols.tables, "fuzz.csv") {
                    Err(e) => assert!(!e.to_string().is_empty()),
                    Ok(per_table) => {
                        for p in &per_table {
                            p.validate().expect("validated parameters");
                        }
                    }
                }
            }
        },
    }
});
