//! The shot study's scenario reader on arbitrary text: never panics; either an error
//! (whose message can be formatted) or a scenario whose accessors work and whose values
//! are what the validation promises.
#![no_main]
use libfuzzer_sys::fuzz_target;

use kisstime::study::StudyConfig;

fuzz_target!(|data: &[u8]| {
    // the reader takes text; bytes that are not UTF-8 are replaced, as a lossy read would
    let text = String::from_utf8_lossy(data);
    match StudyConfig::parse(&text, "fuzz.toml") {
        Ok(s) => {
            s.params.validate().expect("validated parameters");
            assert!(s.balls.len() >= 2);
            assert_ne!(s.cue_ball, s.object_ball);
            let cue = s.cue_spot();
            assert_eq!(cue.id, s.cue_ball);
            let objects = s.object_balls();
            assert_eq!(objects.len(), s.balls.len() - 1);
            assert!(objects.iter().any(|(id, _)| *id == s.object_ball));
            let sigma = s.sigma();
            for (_, v) in sigma.named() {
                assert!(!v.is_nan() && v >= 0.0);
            }
            for b in &s.balls {
                assert!(b.x.is_finite() && b.y.is_finite());
            }
        }
        Err(e) => {
            assert!(!e.to_string().is_empty());
        }
    }
});
