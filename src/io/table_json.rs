//! Tables from JSON: the layout of `data/fullshots/table.json` (pooltool's table
//! description). Objects are read in text order with repeated keys kept — the order of a
//! table's cushions and pockets is pooltool's detection order, and a repeated id is an
//! error, not a silent overwrite — through `serde_json` (with `float_roundtrip`, so
//! `repr`-written floats read back exactly).

use serde::de::{Deserialize, Deserializer, MapAccess, SeqAccess, Visitor};

use crate::error::{Error, InputError, SimError};
use crate::model::sim_params::BallParams;
use crate::model::table::MAX_TABLE_ITEMS;
use crate::model::table::{
    CircularCushion, LinearCushion, POCKET_DEPTH, Pocket, PocketTableSpecs, Table,
};
use crate::model::vec3::Vec3;

/// A JSON value with its objects in text order (repeated keys kept).
#[derive(Clone, Debug, PartialEq)]
pub enum Json {
    /// `null`.
    Null,
    /// `true` or `false`.
    Bool(bool),
    /// A number.
    Num(f64),
    /// A string.
    Str(String),
    /// An array.
    Arr(Vec<Json>),
    /// An object, keys in text order.
    Obj(Vec<(String, Json)>),
}

impl Json {
    /// Parses `text` as one JSON value.
    pub fn parse(text: &str) -> Result<Json, serde_json::Error> {
        serde_json::from_str(text)
    }

    /// The value under `key` of an object (the first, if repeated).
    pub fn get(&self, key: &str) -> Option<&Json> {
        match self {
            Json::Obj(items) => items.iter().find(|(k, _)| k == key).map(|(_, v)| v),
            _ => None,
        }
    }

    /// The number, if this is one.
    pub fn as_f64(&self) -> Option<f64> {
        match self {
            Json::Num(x) => Some(*x),
            _ => None,
        }
    }
}

impl<'de> Deserialize<'de> for Json {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Json, D::Error> {
        d.deserialize_any(JsonVisitor)
    }
}

/// Builds a [`Json`] from what `serde_json` reads.
struct JsonVisitor;

impl<'de> Visitor<'de> for JsonVisitor {
    type Value = Json;

    fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
        f.write_str("a JSON value")
    }
    fn visit_unit<E>(self) -> Result<Json, E> {
        Ok(Json::Null)
    }
    fn visit_bool<E>(self, v: bool) -> Result<Json, E> {
        Ok(Json::Bool(v))
    }
    fn visit_i64<E>(self, v: i64) -> Result<Json, E> {
        Ok(Json::Num(v as f64))
    }
    fn visit_u64<E>(self, v: u64) -> Result<Json, E> {
        Ok(Json::Num(v as f64))
    }
    fn visit_f64<E>(self, v: f64) -> Result<Json, E> {
        Ok(Json::Num(v))
    }
    fn visit_str<E>(self, v: &str) -> Result<Json, E> {
        Ok(Json::Str(v.to_owned()))
    }
    fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<Json, A::Error> {
        let mut items = Vec::new();
        while let Some(v) = seq.next_element()? {
            items.push(v);
        }
        Ok(Json::Arr(items))
    }
    fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<Json, A::Error> {
        let mut items = Vec::new();
        while let Some((k, v)) = map.next_entry()? {
            items.push((k, v));
        }
        Ok(Json::Obj(items))
    }
}

/// The names of the built-in tables ([`table_by_name`]).
pub const BUILTIN_TABLES: [&str; 5] = ["9ft", "7ft", "rectangle", "snooker", "carom"];

/// pooltool's snooker table, `Table.from_game_type(GameType.SNOOKER)` ("Generic Snooker"),
/// as `data/tables/make_tables.py` wrote it.
const SNOOKER_JSON: &str = include_str!("../../data/tables/snooker.json");
/// pooltool's carom table, `Table.from_game_type(GameType.THREECUSHION)` (no pockets).
const CAROM_JSON: &str = include_str!("../../data/tables/billiard.json");

/// The table a name gives, as `kisstime simulate --table` and a study's `[table]` take
/// it: `9ft` is pooltool's 9-ft pocket table ([`Table::nine_foot`]), `7ft` pooltool's
/// default table, `pt.Table.default()` ([`Table::seven_foot`]), `rectangle` the 9-ft
/// playing surface with four plain rails and no pockets, `snooker` and `carom` pooltool's
/// snooker table and three-cushion (billiard) table (`data/tables/snooker.json`,
/// `billiard.json`, built in), and anything else the path of a JSON table
/// ([`Table::from_json`]). Errors name the file.
pub fn table_by_name(name: &str) -> Result<Table, Error> {
    match name {
        "9ft" => Ok(Table::nine_foot()),
        "7ft" => Ok(Table::seven_foot()),
        "rectangle" => {
            let s = PocketTableSpecs::default();
            Table::rectangle(s.w, s.l, s.cushion_height).map_err(Error::from)
        }
        "snooker" => table_from_json_text(SNOOKER_JSON, "the built-in snooker table"),
        "carom" => table_from_json_text(CAROM_JSON, "the built-in carom table"),
        path => {
            let text = std::fs::read_to_string(path).map_err(|source| Error::Io {
                path: path.to_owned(),
                source,
            })?;
            table_from_json_text(&text, path)
        }
    }
}

/// The balls a table is played with, as pooltool's `BallParams.default(game_type)` gives
/// them for the table's game: snooker balls ([`BallParams::snooker`]) on `snooker`, carom
/// balls ([`BallParams::carom`]) on `carom`, pool balls ([`BallParams::default`]) on every
/// other table (the pocket tables and any file). What `simulate` and a study use when no
/// physics is given.
pub fn default_ball_params(table_name: &str) -> BallParams {
    match table_name {
        "snooker" => BallParams::snooker(),
        "carom" => BallParams::carom(),
        _ => BallParams::default(),
    }
}

/// A table from JSON text ([`Table::from_json`]: the table object, or a whole
/// `table.json` with the table under `"table"`) that did not come from a file, e.g. what
/// `kisstime.pooltool.table_json` produces; errors name it `source` as they would name a
/// file.
pub fn table_from_json_text(text: &str, source: &str) -> Result<Table, Error> {
    Table::from_json(text).map_err(|e| InputError::new(e.to_string()).in_file(source).into())
}

impl Table {
    /// A table from JSON in the format of `data/fullshots/table.json`: either that whole
    /// file (the table under `"table"`) or the table object itself, with
    /// `linear_cushion_segments` (`{id: {p1: [x,y,z], p2: [x,y,z], direction}}`),
    /// `circular_cushion_segments` (`{id: {center: [x,y,z], radius}}`) and `pockets`
    /// (`{id: {center: [x,y,z], radius, depth?}}`; depth defaults to
    /// [`POCKET_DEPTH`]). Key order is kept: it is the detection order.
    ///
    /// Errors (never panics) on malformed JSON, non-finite numbers, a zero-length segment,
    /// a direction other than 0, 1, 2, a non-positive radius, a negative depth, a
    /// repeated id, or more than [`MAX_TABLE_ITEMS`] items of one kind.
    /// (Pocket `a`/`b` fields and anything else unknown are ignored.)
    pub fn from_json(text: &str) -> Result<Table, SimError> {
        let value = Json::parse(text).map_err(|e| SimError::Table(format!("bad JSON: {e}")))?;
        let table = value.get("table").unwrap_or(&value);
        if !matches!(table, Json::Obj(_)) {
            return Err(SimError::Table(
                "the table must be a JSON object".to_owned(),
            ));
        }
        let mut t = Table::empty();
        for (id, s) in section(table, "linear_cushion_segments")? {
            let what = format!("linear segment {id}");
            t.linear.push(linear_from_json(s, &what)?);
            t.linear_ids.push(id.clone());
        }
        for (id, c) in section(table, "circular_cushion_segments")? {
            let what = format!("circular segment {id}");
            let center = point(c.get("center"), &what)?;
            let radius = positive(c.get("radius"), &format!("{what} radius"))?;
            t.circular.push(CircularCushion { center, radius });
            t.circular_ids.push(id.clone());
        }
        for (id, p) in section(table, "pockets")? {
            t.pockets
                .push(pocket_from_json(p, &format!("pocket {id}"))?);
            t.pocket_ids.push(id.clone());
        }
        Ok(t)
    }
}

/// The `(id, item)` pairs of one section (an object; missing means empty), checked for
/// size and repeated ids.
fn section<'j>(table: &'j Json, name: &str) -> Result<&'j [(String, Json)], SimError> {
    let items: &[(String, Json)] = match table.get(name) {
        None => &[],
        Some(Json::Obj(items)) => items,
        Some(_) => return Err(SimError::Table(format!("{name} must be an object"))),
    };
    if items.len() > MAX_TABLE_ITEMS {
        return Err(SimError::Table(format!(
            "{name}: {} items, at most {MAX_TABLE_ITEMS}",
            items.len()
        )));
    }
    for (k, (id, _)) in items.iter().enumerate() {
        if items[..k].iter().any(|(other, _)| other == id) {
            return Err(SimError::Table(format!("{name}: repeated id {id:?}")));
        }
    }
    Ok(items)
}

/// A straight segment from `{p1, p2, direction}`.
fn linear_from_json(s: &Json, what: &str) -> Result<LinearCushion, SimError> {
    let p1 = point(s.get("p1"), what)?;
    let p2 = point(s.get("p2"), what)?;
    if p1.x == p2.x && p1.y == p2.y {
        return Err(SimError::Table(format!("{what}: zero length")));
    }
    let dir = s.get("direction").and_then(Json::as_f64);
    let direction = match dir {
        Some(d) if d == 0.0 || d == 1.0 || d == 2.0 => d as u32,
        _ => {
            return Err(SimError::Table(format!(
                "{what}: direction must be 0, 1 or 2"
            )));
        }
    };
    Ok(LinearCushion::new(p1, p2, direction))
}

/// A pocket from `{center, radius, depth?}`.
fn pocket_from_json(p: &Json, what: &str) -> Result<Pocket, SimError> {
    let center = point(p.get("center"), what)?;
    let radius = positive(p.get("radius"), &format!("{what} radius"))?;
    let depth = match p.get("depth") {
        None => POCKET_DEPTH,
        Some(d) => d.as_f64().unwrap_or(f64::NAN),
    };
    if !(depth.is_finite() && depth >= 0.0) {
        return Err(SimError::Table(format!("{what}: depth = {depth}")));
    }
    Ok(Pocket {
        center,
        radius,
        depth,
    })
}

/// A JSON point `[x, y, z]` (or `[x, y]`, z = 0), checked finite.
fn point(v: Option<&Json>, what: &str) -> Result<Vec3, SimError> {
    let nums: Vec<f64> = match v {
        Some(Json::Arr(items)) => items.iter().filter_map(Json::as_f64).collect(),
        _ => Vec::new(),
    };
    let n_items = match v {
        Some(Json::Arr(items)) => items.len(),
        _ => 0,
    };
    let p = match (nums.as_slice(), n_items) {
        ([x, y], 2) => Vec3::new(*x, *y, 0.0),
        ([x, y, z], 3) => Vec3::new(*x, *y, *z),
        _ => {
            return Err(SimError::Table(format!(
                "{what}: a point needs 2 or 3 numbers"
            )));
        }
    };
    if !p.is_finite() {
        return Err(SimError::Table(format!("{what}: non-finite coordinate")));
    }
    Ok(p)
}

fn positive(v: Option<&Json>, what: &str) -> Result<f64, SimError> {
    match v.and_then(Json::as_f64) {
        Some(x) if x.is_finite() && x > 0.0 => Ok(x),
        other => Err(SimError::Table(format!(
            "{what} = {other:?} must be a positive number"
        ))),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn reference_json() -> String {
        let path = concat!(env!("CARGO_MANIFEST_DIR"), "/data/fullshots/table.json");
        std::fs::read_to_string(path).expect("data/fullshots/table.json in the repository")
    }

    fn max_diff(a: &Table, b: &Table) -> f64 {
        let mut d: f64 = 0.0;
        for (s, t) in a.linear.iter().zip(&b.linear) {
            d = d.max((s.p1 - t.p1).norm()).max((s.p2 - t.p2).norm());
            d = d.max((s.lx - t.lx).abs()).max((s.l0 - t.l0).abs());
        }
        for (s, t) in a.circular.iter().zip(&b.circular) {
            d = d
                .max((s.center - t.center).norm())
                .max((s.radius - t.radius).abs());
        }
        for (s, t) in a.pockets.iter().zip(&b.pockets) {
            d = d
                .max((s.center - t.center).norm())
                .max((s.radius - t.radius).abs());
        }
        d
    }

    #[test]
    fn nine_foot_table_matches_pooltools() {
        let built = Table::nine_foot();
        let loaded = Table::from_json(&reference_json()).unwrap();
        assert_eq!(built.linear_ids, loaded.linear_ids);
        assert_eq!(built.circular_ids, loaded.circular_ids);
        assert_eq!(built.pocket_ids, loaded.pocket_ids);
        for (a, b) in built.linear.iter().zip(&loaded.linear) {
            assert_eq!(a.direction, b.direction);
        }
        let d = max_diff(&built, &loaded);
        assert_eq!(d, 0.0, "built vs table.json differ by {d}");
    }

    fn data_table(name: &str) -> Table {
        let path = format!("{}/data/tables/{name}", env!("CARGO_MANIFEST_DIR"));
        table_by_name(&path).unwrap_or_else(|e| panic!("{path}: {e}"))
    }

    #[test]
    fn seven_foot_table_is_pooltools_default_table() {
        // data/tables/7ft.json is pooltool's Table.default() (data/tables/make_tables.py)
        let built = table_by_name("7ft").unwrap();
        let loaded = data_table("7ft.json");
        assert_eq!(built.linear_ids, loaded.linear_ids);
        assert_eq!(built.circular_ids, loaded.circular_ids);
        assert_eq!(built.pocket_ids, loaded.pocket_ids);
        for (a, b) in built.linear.iter().zip(&loaded.linear) {
            assert_eq!(a.direction, b.direction);
        }
        for (a, b) in built.pockets.iter().zip(&loaded.pockets) {
            assert_eq!(a.depth, b.depth);
        }
        assert_eq!(max_diff(&built, &loaded), 0.0);
        assert_eq!(built.linear.len(), 18);
        // not the 9-ft table
        assert!(max_diff(&built, &Table::nine_foot()) > 0.1);
    }

    #[test]
    fn pooltools_snooker_and_billiard_tables_load() {
        let snooker = data_table("snooker.json");
        assert_eq!(
            (
                snooker.linear.len(),
                snooker.circular.len(),
                snooker.pockets.len()
            ),
            (18, 12, 6)
        );
        let billiard = data_table("billiard.json");
        assert_eq!(
            (
                billiard.linear.len(),
                billiard.circular.len(),
                billiard.pockets.len()
            ),
            (4, 0, 0)
        );
        assert_eq!(billiard.linear_ids, ["3", "12", "9", "18"]);
    }

    #[test]
    fn json_text_is_a_table_and_its_errors_name_the_source() {
        let text = reference_json();
        let t = table_from_json_text(&text, "table").unwrap();
        assert_eq!(max_diff(&t, &Table::nine_foot()), 0.0);
        let err = table_from_json_text("{\"pockets\": 3}", "table").unwrap_err();
        let msg = err.to_string();
        assert!(msg.contains("table") && msg.contains("pockets"), "{msg}");
    }

    #[test]
    fn bad_table_files_are_errors_and_key_order_is_kept() {
        assert!(Table::from_json("{").is_err());
        let zero =
            r#"{"linear_cushion_segments": {"a": {"p1": [0,0,0], "p2": [0,0,0], "direction": 0}}}"#;
        assert!(
            Table::from_json(zero)
                .unwrap_err()
                .to_string()
                .contains("zero length")
        );
        let dir =
            r#"{"linear_cushion_segments": {"a": {"p1": [0,0,0], "p2": [1,0,0], "direction": 7}}}"#;
        assert!(Table::from_json(dir).is_err());
        let rad = r#"{"pockets": {"p": {"center": [0,0,0], "radius": -1}}}"#;
        assert!(
            Table::from_json(rad)
                .unwrap_err()
                .to_string()
                .contains("radius")
        );
        let order = r#"{"pockets": {"z": {"center": [0,0,0], "radius": 1}, "a": {"center": [1,0,0], "radius": 1}}}"#;
        assert_eq!(Table::from_json(order).unwrap().pocket_ids, ["z", "a"]);
    }

    #[test]
    fn repeated_ids_and_exact_floats() {
        let twice = r#"{"pockets": {"p": {"center": [0,0,0], "radius": 1}, "p": {"center": [1,0,0], "radius": 1}}}"#;
        let err = Table::from_json(twice).unwrap_err().to_string();
        assert!(err.contains("repeated id"), "{err}");
        // a float that a naive parser rounds off by an ulp
        let text = r#"{"pockets": {"p": {"center": [0.1234567890123456789, 2.2250738585072011e-308, 0], "radius": 1}}}"#;
        let t = Table::from_json(text).unwrap();
        assert_eq!(
            t.pockets[0].center.x,
            "0.1234567890123456789".parse::<f64>().unwrap()
        );
        assert_eq!(
            t.pockets[0].center.y,
            "2.2250738585072011e-308".parse::<f64>().unwrap()
        );
    }
}
