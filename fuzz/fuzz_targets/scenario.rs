//! The shot study's scenario reader on arbitrary text: never panics; either an error
//! (whose message can be formatted) or a scenario whose accessors work and whose values
//! are what the validation promises — and whose intended shot simulates to the end.
#![no_main]
use libfuzzer_sys::fuzz_target;

use kisstime::simulate::{EventLoop, Limits};
use kisstime::study::StudyConfig;

fuzz_target!(|data: &[u8]| {
    // the reader takes text; bytes that are not UTF-8 are replaced, as a lossy read would
    let text = String::from_utf8_lossy(data);
    match StudyConfig::parse(&text, "fuzz.toml", None) {
        Ok(s) => {
            s.params.validate().expect("validated parameters");
            assert!(s.balls.len() >= 2);
            assert_ne!(s.cue, s.intended);
            assert!(s.cue < s.balls.len() && s.intended < s.balls.len());
            assert!(s.pocket.is_none_or(|p| p < s.table.pockets.len()));
            let sigma = s.sigma();
            for (_, v) in sigma.named() {
                assert!(!v.is_nan() && v >= 0.0);
            }
            for b in &s.balls {
                assert!(b.x.is_finite() && b.y.is_finite());
            }
            s.shot.validate().expect("a validated strike");
            // the intended shot runs (capped) without a panic
            let limits = Limits {
                max_events: 2_000,
                max_time: 60.0,
            };
            let mut lp = EventLoop::new(&s.table, s.params, limits, s.balls.len())
                .expect("validated parameters");
            lp.reset(&s.initial(), Some((s.cue, s.shot)))
                .expect("a validated layout");
            while lp.step().is_some() {}
        }
        Err(e) => {
            assert!(!e.to_string().is_empty());
        }
    }
});
