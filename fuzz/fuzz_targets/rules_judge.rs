//! The rules judges (`game::Rules::judge` on a `Shot { ids, start, events }` in a
//! `Context`) on arbitrary shots, for every game: never panics; an error whose message
//! formats, or a verdict that holds together (`foul` is `None` exactly when `legal`; a
//! won game is over; no points but in the scoring games, snooker and three-cushion).
//!
//! The bytes decode (`fuzz/shared/bytes.rs`) to up to 24 balls (sometimes up to 70), their
//! ids (mostly a game's: the cue ball 0 and distinct object balls 1–21; sometimes any
//! integer, repeated or missing the cue ball), their start states (any motion label,
//! pocketed ones included), up to 64 events of any kind whose agents are mostly balls and
//! items that exist (sometimes any `u32`) and whose times mostly do not go back (sometimes
//! any f64, NaN included), and an arbitrary context (any hittable set, called ball and
//! pocket, break flag, WPA flag and score, `u32::MAX` included).
#![no_main]
use libfuzzer_sys::fuzz_target;

#[path = "../shared/bytes.rs"]
mod bytes;
use bytes::Bytes;

use kisstime::MotionState;
use kisstime::game::{Context, Rules, Shot};
use kisstime::simulate::{BallState, Event, EventKind, EventRecord, NO_AGENT};

const KINDS: [EventKind; 9] = [
    EventKind::StickBall,
    EventKind::BallBall,
    EventKind::BallLinearCushion,
    EventKind::BallCircularCushion,
    EventKind::BallPocket,
    EventKind::SlidingRolling,
    EventKind::RollingSpinning,
    EventKind::RollingStationary,
    EventKind::SpinningStationary,
];

const STATES: [MotionState; 5] = [
    MotionState::Stationary,
    MotionState::Spinning,
    MotionState::Sliding,
    MotionState::Rolling,
    MotionState::Pocketed,
];

fn any_i64(bytes: &mut Bytes) -> i64 {
    match bytes.u8() % 4 {
        0 => bytes.u64() as i64,
        1 => -(bytes.u8() as i64),
        _ => bytes.u8() as i64 % 24,
    }
}

fuzz_target!(|data: &[u8]| {
    let mut bytes = Bytes::new(data);
    let n = if bytes.one_in(16) {
        bytes.u8() as usize % 71
    } else {
        bytes.u8() as usize % 25
    };
    // ids: a game's (cue ball first, distinct numbers), or anything
    let mut ids: Vec<i64> = Vec::with_capacity(n);
    let wild = bytes.one_in(8);
    let mut next = 0i64;
    for _ in 0..n {
        if wild {
            ids.push(any_i64(&mut bytes));
        } else {
            ids.push(next);
            next += 1 + (bytes.u8() % 3) as i64;
        }
    }
    if !wild && n > 1 && bytes.one_in(2) {
        // shuffle the cue ball somewhere else
        let k = bytes.u8() as usize % n;
        ids.swap(0, k);
    }
    let start: Vec<BallState> = (0..n)
        .map(|_| {
            let mut b = BallState::at_rest(bytes.unit(), 2.0 * bytes.unit(), 0.028575);
            if bytes.one_in(4) {
                b.s = STATES[bytes.u8() as usize % STATES.len()];
            }
            b
        })
        .collect();
    let n_events = bytes.u8() as usize % 65;
    let mut t = 0.0;
    let mut events = Vec::with_capacity(n_events);
    let any_agent = |bytes: &mut Bytes, range: usize| -> u32 {
        if bytes.one_in(16) {
            bytes.u32()
        } else {
            (bytes.u8() as usize % range.max(1)) as u32
        }
    };
    for k in 0..n_events {
        let kind = if k == 0 && !bytes.one_in(8) {
            EventKind::StickBall
        } else {
            KINDS[bytes.u8() as usize % KINDS.len()]
        };
        let ball = any_agent(&mut bytes, n);
        let other = match kind {
            EventKind::BallBall => any_agent(&mut bytes, n),
            EventKind::BallLinearCushion => any_agent(&mut bytes, 18),
            EventKind::BallCircularCushion => any_agent(&mut bytes, 12),
            EventKind::BallPocket => any_agent(&mut bytes, 6),
            _ => {
                if bytes.one_in(16) {
                    bytes.u32()
                } else {
                    NO_AGENT
                }
            }
        };
        t = if bytes.one_in(16) {
            bytes.raw_f64()
        } else {
            t + bytes.unit()
        };
        let event = Event {
            kind,
            t,
            ball,
            other,
        };
        let state = BallState::at_rest(0.5, 0.5, 0.028575);
        events.push(EventRecord {
            event,
            states: [state, state],
        });
    }
    let opt = |bytes: &mut Bytes| bytes.one_in(2);
    let context = Context {
        break_shot: opt(&mut bytes),
        hittable: bytes.u32(),
        call_shot: opt(&mut bytes),
        ball_call: if opt(&mut bytes) {
            Some(any_i64(&mut bytes))
        } else {
            None
        },
        pocket_call: if opt(&mut bytes) {
            Some(if bytes.one_in(8) {
                bytes.u64() as usize
            } else {
                bytes.u8() as usize % 8
            })
        } else {
            None
        },
        wpa: opt(&mut bytes),
        score: if bytes.one_in(8) {
            [u32::MAX, u32::MAX - bytes.u8() as u32]
        } else {
            [bytes.u8() as u32, bytes.u8() as u32]
        },
    };
    let shot = Shot {
        ids: &ids,
        start: &start,
        events: &events,
    };
    for (rules, _) in Rules::ALL {
        let _ = rules
            .check_context(&context)
            .map_err(|e| assert!(!e.is_empty()));
        let context = rules.context(context);
        match rules.judge(&shot, &context) {
            Err(e) => assert!(!e.to_string().is_empty()),
            Ok(v) => {
                assert_eq!(v.legal, v.foul.is_none(), "{rules:?}: {v:?}");
                assert!(!v.won || v.game_over, "{rules:?}: {v:?}");
                if !rules.scores() {
                    assert_eq!((v.points, v.foul_points), (0, 0), "{rules:?}: {v:?}");
                }
            }
        }
    }
});
