//! Comparing two backends' answers under the tolerance tiers of the ground-truth corpus
//! (`tests/data/README.md`), with the CPU f64 answers as the reference.
//!
//! Without a 50-digit truth, the tier's grazing excuse is decided from the reference
//! itself: a pair is excused when moving the contact distance `2R` by the tier's margin
//! (1e-5 m for f32, 1e-7 m for f64) flips the f64 answer between hit and miss — it then
//! grazes within that margin. A hit's time agrees when it is within `1e-6 + 1e-6·t` s
//! (f32; `1e-9 + 1e-6·t` s for f64) or its gap error `|Δt|·v_n` is within what the precision
//! can resolve (`1e-5 m + 5e-7·S` for f32, `S` the length of the relative path; `1e-9 m` for
//! f64).

use crate::batch::{Batch, NextCollision, pair_index, pairs};
use crate::model::{Params, Precision, dot, norm};
use crate::motion::path::ball_path;
use crate::query::ball_ball::{Contact, RelPath, Status, pair_contact};

/// How two sets of per-pair answers agree.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Agreement {
    /// Pairs compared.
    pub pairs: usize,
    /// Pairs whose answers differ beyond the tier and that do not graze: should be 0.
    pub outside_tier: usize,
    /// Pairs whose classification or time differ but that graze within the tier's margin.
    pub excused: usize,
}

/// The tier's grazing margin in metres.
pub fn excuse_margin(precision: Precision) -> f64 {
    match precision {
        Precision::F32 => 1e-5,
        Precision::F64 => 1e-7,
    }
}

/// Whether the f64 answer for balls `i`, `j` of table `k` flips between hit and miss when
/// the contact distance moves by `delta`: the pair grazes within `delta`.
pub fn grazes(batch: &Batch, k: usize, i: usize, j: usize, params: &Params, delta: f64) -> bool {
    let answer = |radius: f64| {
        let p = Params { radius, ..*params };
        let b = batch.balls(k);
        pair_contact(&ball_path(&b[i], &p), &ball_path(&b[j], &p), radius).status
    };
    answer(params.radius - 0.5 * delta) != answer(params.radius + 0.5 * delta)
}

/// Whether `t_other` agrees with the reference hit time `t_ref` of the relative path `rel`
/// under the tier of `precision` (module docs).
pub fn time_agrees(rel: &RelPath, t_ref: f64, t_other: f64, precision: Precision) -> bool {
    let dt = (t_other - t_ref).abs();
    let ct = rel.at(t_ref);
    let vn = (dot(ct, rel.velocity_at(t_ref)) / norm(ct)).abs();
    let scale = norm(rel.c) + norm(rel.b) * t_ref + norm(rel.a) * t_ref * t_ref;
    match precision {
        Precision::F32 => dt <= 1e-6 + 1e-6 * t_ref || dt * vn <= 1e-5 + 5e-7 * scale,
        Precision::F64 => dt <= 1e-9 + 1e-6 * t_ref || dt * vn <= 1e-9,
    }
}

/// Whether two answers for one pair agree under the tier (before any grazing excuse).
fn answers_agree(rel: &RelPath, r: Contact, o: Contact, precision: Precision) -> bool {
    match (r.status, o.status) {
        (Status::None, Status::None) | (Status::Overlap, Status::Overlap) => true,
        (Status::Hit, Status::Hit) => time_agrees(rel, r.t, o.t, precision),
        // touching at 0 within the precision's contact tolerance
        (Status::Overlap, Status::Hit) | (Status::Hit, Status::Overlap) => r.t == 0.0 && o.t == 0.0,
        _ => false,
    }
}

/// Compares per-pair answers `other` (computed in `precision`) with the f64 `reference`,
/// both in pair order for `batch`. `report` receives each pair outside the tier as
/// `(table position, i, j, reference, other)`.
pub fn compare_pairs(
    batch: &Batch,
    params: &Params,
    reference: &[Contact],
    other: &[Contact],
    precision: Precision,
    mut report: impl FnMut(usize, usize, usize, Contact, Contact),
) -> Agreement {
    let mut agreement = Agreement {
        pairs: reference.len().min(other.len()),
        ..Agreement::default()
    };
    let mut at = 0;
    for k in 0..batch.num_tables() {
        let balls = batch.balls(k);
        for (i, j) in pairs(balls.len()) {
            let (r, o) = (reference[at], other[at]);
            at += 1;
            let rel =
                RelPath::between(&ball_path(&balls[i], params), &ball_path(&balls[j], params));
            if answers_agree(&rel, r, o, precision) {
                continue;
            }
            if grazes(batch, k, i, j, params, excuse_margin(precision)) {
                agreement.excused += 1;
            } else {
                agreement.outside_tier += 1;
                report(k, i, j, r, o);
            }
        }
    }
    agreement
}

/// Counts the tables whose next collision differs from the reference's in a way the tier
/// does not explain. Another pair is explained by a near-tie (the reference's own time for
/// that pair within `1e-5 + 1e-5·t` s of its best) or, when only one side found a
/// collision, by that pair grazing within the tier's margin. `reference_pairs` are the f64
/// per-pair answers in pair order.
pub fn next_disagreements(
    batch: &Batch,
    params: &Params,
    precision: Precision,
    reference_pairs: &[Contact],
    reference: &[NextCollision],
    other: &[NextCollision],
) -> usize {
    let mut bad = 0;
    for (k, (r, o)) in reference.iter().zip(other).enumerate() {
        if r.pair == o.pair {
            continue;
        }
        let ids = batch.ball_ids(k);
        let local = |(i, j): (i64, i64)| {
            let i = ids.iter().position(|&b| b == i)?;
            let j = ids.iter().position(|&b| b == j)?;
            Some((i, j))
        };
        let explained = match (r.pair.and_then(local), o.pair.and_then(local)) {
            (Some(_), Some((i, j))) => {
                let c = reference_pairs[batch.pair_range(k).start + pair_index(ids.len(), i, j)];
                c.status.is_contact() && (c.t - r.t).abs() <= 1e-5 + 1e-5 * r.t
            }
            (Some((i, j)), None) | (None, Some((i, j))) => {
                grazes(batch, k, i, j, params, excuse_margin(precision))
            }
            (None, None) => false,
        };
        if !explained {
            bad += 1;
        }
    }
    bad
}
