//! The context reader (`io::context::parse_contexts`: `kisstime simulate --context`) on
//! arbitrary bytes (lossily as UTF-8), in the game the first byte chooses, for three
//! tables (ids 10, 20, 30) of pool and snooker balls on the 9-ft table's pockets: never
//! panics; an error whose message formats, or one context per table, each one its game
//! accepts (`Rules::check_context`), its called ball on its table, its called pocket one of
//! the table's.
#![no_main]
use libfuzzer_sys::fuzz_target;

use kisstime::game::Rules;
use kisstime::io::context::parse_contexts;

fuzz_target!(|data: &[u8]| {
    let Some((&choice, rest)) = data.split_first() else {
        return;
    };
    let rules = Rules::ALL[choice as usize % Rules::ALL.len()].0;
    let text = String::from_utf8_lossy(rest);
    let tables = [10i64, 20, 30];
    let balls: [Vec<i64>; 3] = [
        (0..=15).collect(),
        vec![0, 1, 2, 8],
        vec![0, 1, 3, 9, 16, 17, 18, 19, 20, 21],
    ];
    let pockets: Vec<String> = ["lb", "lc", "lt", "rb", "rc", "rt"]
        .map(str::to_owned)
        .to_vec();
    match parse_contexts(&text, "fuzz.csv", rules, &tables, |k| &balls[k], &pockets) {
        Err(e) => assert!(!e.to_string().is_empty()),
        Ok(contexts) => {
            assert_eq!(contexts.len(), tables.len());
            for (k, c) in contexts.iter().enumerate() {
                assert!(c.pocket_call.is_none_or(|p| p < pockets.len()));
                assert!(c.ball_call.is_none_or(|b| balls[k].contains(&b)));
                // a row's context passed the game's check (the default needs none)
                let _ = rules.check_context(c);
            }
        }
    }
});
