//! The table JSON reader (`io::table_json::table_from_json_text`, i.e. `Table::from_json`)
//! on arbitrary bytes (lossily as UTF-8): never panics; an error whose message formats, or
//! a table that holds what the reader promises (every number finite, segments of non-zero
//! length, directions 0–2, positive radii, non-negative depths, as many ids as items, no
//! repeated id) and on which a short shot (two balls, capped at 200 events or 10 s) runs
//! without a panic, its errors formatting and its event times non-decreasing.
#![no_main]
use libfuzzer_sys::fuzz_target;

use std::collections::HashSet;

use kisstime::io::table_json::table_from_json_text;
use kisstime::simulate::{BallState, CueStrike, Limits, SimParams, simulate};

fn unique(ids: &[String]) -> bool {
    ids.iter().collect::<HashSet<_>>().len() == ids.len()
}

fuzz_target!(|data: &[u8]| {
    let text = String::from_utf8_lossy(data);
    match table_from_json_text(&text, "fuzz.json") {
        Err(e) => assert!(!e.to_string().is_empty()),
        Ok(t) => {
            assert_eq!(t.linear.len(), t.linear_ids.len());
            assert_eq!(t.circular.len(), t.circular_ids.len());
            assert_eq!(t.pockets.len(), t.pocket_ids.len());
            assert!(unique(&t.linear_ids) && unique(&t.circular_ids) && unique(&t.pocket_ids));
            for s in &t.linear {
                assert!(s.p1.is_finite() && s.p2.is_finite());
                assert!(
                    s.p1.x != s.p2.x || s.p1.y != s.p2.y,
                    "a zero-length segment"
                );
            }
            for c in &t.circular {
                assert!(c.center.is_finite() && c.radius.is_finite() && c.radius > 0.0);
            }
            for p in &t.pockets {
                assert!(p.center.is_finite() && p.radius.is_finite() && p.radius > 0.0);
                assert!(p.depth.is_finite() && p.depth >= 0.0);
            }
            // a short shot on it: no panic, whatever the table
            let p = SimParams::default();
            let balls = [
                BallState::at_rest(0.6, 0.6, p.ball.r),
                BallState::at_rest(0.65, 1.9, p.ball.r),
            ];
            let strike = CueStrike {
                v0: 3.0,
                phi: 85.0,
                theta: 0.0,
                a: 0.1,
                b: 0.2,
            };
            let limits = Limits {
                max_events: 200,
                max_time: 10.0,
            };
            let mut last = 0.0;
            match simulate(&t, p, limits, &balls, Some((0, strike)), |e, _| {
                assert!(e.t >= last, "event times go back: {} after {last}", e.t);
                last = e.t;
            }) {
                Ok(out) => assert!(out.n_events <= 200),
                Err(e) => assert!(!e.to_string().is_empty()),
            }
        }
    }
});
