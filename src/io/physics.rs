//! The simulator's physical parameters as text, in pooltool 0.6.0's vocabulary: one parser
//! for every entry point (`kisstime simulate --physics`, `kisstime shots --physics`, a
//! study's `[physics]` table, a `.json` scenario's and a pooltool table JSON's
//! `ball_params`, Python's `physics={...}`), so that every one takes the same keys and
//! refuses the same mistakes with the same message.
//!
//! # The format
//!
//! A TOML file (`data/physics/physics.toml` is one), every key optional (pooltool's
//! default where left out), the ball's keys flat at the top level with the names of
//! pooltool's `BallParams` ([`BALL_KEYS`]) and the cue's in an optional `[cue]` table
//! with the names of pooltool's `CueSpecs` ([`CUE_KEYS`]):
//!
//! ```toml
//! m = 0.170097                  # ball mass, kg
//! R = 0.028575                  # ball radius, m
//! u_s = 0.2                     # sliding friction
//! u_r = 0.01                    # rolling resistance
//! u_sp_proportionality = 0.4444444444444444   # spinning friction u_sp = this × R (a length)
//! u_b = 0.05                    # ball–ball friction, > 0 (unused by the default resolver)
//! e_b = 0.95                    # ball–ball restitution, in (0, 1]
//! e_c = 0.85                    # cushion restitution, in (0, 1]
//! f_c = 0.2                     # cushion friction, > 0
//! g = 9.81                      # gravity, m/s²
//!
//! [cue]
//! M = 0.567                     # cue mass, kg
//! end_mass = 0.0056699          # the cue's end mass (squirt), kg; default 0.170097 / 30
//! ```
//!
//! As in pooltool, `u_sp` is not a parameter but the product `u_sp_proportionality · R`
//! (so changing `R` alone scales the spinning friction with it), and the cue's
//! `end_mass` default is pooltool's constant `0.170097 / 30` whatever `m` is. The
//! resolver's constants ([`crate::model::ResolverParams`]) are pooltool's default
//! resolver's and are not set here.
//!
//! # Errors
//!
//! Every error is an [`Error::Input`] naming the file (or the source given) and the key,
//! and the line where the text is known: a key that is not one of pooltool's names (one
//! of kisstime's former names — `radius`, `ball_mass`, `mu_s`, `mu_r`, `mu_sp`,
//! `cue_mass`, … — says which pooltool name replaces it), a value that is not a number,
//! and a value out of range ([`SimParams::validate`]: the masses, `R`, `u_s`, `u_r`,
//! `u_sp_proportionality`, `g` finite and greater than 0, `e_b` and `e_c` in `(0, 1]`,
//! `u_b` and `f_c` finite and not negative). Nothing here panics on user data.

use std::path::Path;

use crate::error::{Error, InputError, SimError};
use crate::model::sim_params::{
    BallParams, CueParams, DEFAULT_U_SP_PROPORTIONALITY, ResolverParams, SimParams,
};

/// pooltool 0.6.0's `BallParams` field names, the top-level keys, in pooltool's order.
pub const BALL_KEYS: [&str; 10] = [
    "m",
    "R",
    "u_s",
    "u_r",
    "u_sp_proportionality",
    "u_b",
    "e_b",
    "e_c",
    "f_c",
    "g",
];

/// pooltool 0.6.0's `CueSpecs` fields that the physics uses, the keys of the `[cue]` table.
pub const CUE_KEYS: [&str; 2] = ["M", "end_mass"];

/// The table that holds the cue's keys.
pub const CUE_TABLE: &str = "cue";

/// A value as the parser sees it, whatever the text format (TOML, JSON).
#[derive(Clone, Debug, PartialEq)]
pub enum PhysicsValue {
    /// A number (an integer is taken as the float it names).
    Num(f64),
    /// A table (an object), its keys in the text's order where the format keeps it.
    Table(Vec<(String, PhysicsValue)>),
    /// Anything else: what it is, for the message (`a string`, `a boolean`, …).
    Other(&'static str),
}

impl PhysicsValue {
    /// A TOML value.
    pub fn from_toml(v: &toml::Value) -> PhysicsValue {
        match v {
            toml::Value::Integer(i) => PhysicsValue::Num(*i as f64),
            toml::Value::Float(x) => PhysicsValue::Num(*x),
            toml::Value::Table(t) => PhysicsValue::from_toml_table(t),
            toml::Value::String(_) => PhysicsValue::Other("a string"),
            toml::Value::Boolean(_) => PhysicsValue::Other("a boolean"),
            toml::Value::Array(_) => PhysicsValue::Other("an array"),
            toml::Value::Datetime(_) => PhysicsValue::Other("a date"),
        }
    }

    /// A TOML table.
    pub fn from_toml_table(t: &toml::Table) -> PhysicsValue {
        PhysicsValue::Table(
            t.iter()
                .map(|(k, v)| (k.clone(), PhysicsValue::from_toml(v)))
                .collect(),
        )
    }

    /// A JSON value.
    pub fn from_json(v: &serde_json::Value) -> PhysicsValue {
        match v {
            serde_json::Value::Number(n) => match n.as_f64() {
                Some(x) => PhysicsValue::Num(x),
                None => PhysicsValue::Other("a number beyond f64"),
            },
            serde_json::Value::Object(o) => PhysicsValue::Table(
                o.iter()
                    .map(|(k, v)| (k.clone(), PhysicsValue::from_json(v)))
                    .collect(),
            ),
            serde_json::Value::String(_) => PhysicsValue::Other("a string"),
            serde_json::Value::Bool(_) => PhysicsValue::Other("a boolean"),
            serde_json::Value::Array(_) => PhysicsValue::Other("an array"),
            serde_json::Value::Null => PhysicsValue::Other("null"),
        }
    }

    /// What the value is, for messages.
    fn kind(&self) -> &'static str {
        match self {
            PhysicsValue::Num(_) => "a number",
            PhysicsValue::Table(_) => "a table",
            PhysicsValue::Other(what) => what,
        }
    }
}

/// Where parameters come from, for the messages: the file (or source name), the key
/// prefix under which the parameters sit in it (`""` for a physics file, `"physics."` in
/// a study, `"ball_params."` in a table JSON), and the text, to find a key's line.
#[derive(Clone, Copy, Debug)]
pub struct PhysicsSource<'a> {
    /// The file name (or `physics`, `scenario dict`, … when there is no file).
    pub file: &'a str,
    /// The keys' prefix, ending in `.` (or empty).
    pub prefix: &'a str,
    /// The TOML text the values came from, if any (for line numbers).
    pub toml_text: Option<&'a str>,
}

impl PhysicsSource<'_> {
    /// An input error naming the file (and the line of `key` in the TOML text, if found).
    fn error(&self, key: &str, message: String) -> Error {
        let mut e = InputError::new(message).in_file(self.file);
        if let Some(line) = self
            .toml_text
            .and_then(|t| line_of_key(t, self.prefix, key))
        {
            e = e.at_line(line);
        }
        e.into()
    }

    /// `key` with the prefix, as messages name it.
    fn full(&self, key: &str) -> String {
        format!("{}{key}", self.prefix)
    }
}

/// The 1-based line that assigns `key` (a top-level key like `R`, or `cue.M`) under
/// `prefix` (`""` or `"physics."`) in TOML `text`, by a plain scan of `[table]` headers
/// and `key = …` lines: `None` where the text spells it another way (dotted keys, inline
/// tables). Only for messages.
fn line_of_key(text: &str, prefix: &str, key: &str) -> Option<u64> {
    let full = format!("{prefix}{key}");
    let (table, name) = match full.rsplit_once('.') {
        Some((t, n)) => (t.to_owned(), n.to_owned()),
        None => (String::new(), full.clone()),
    };
    let mut current = String::new();
    for (k, line) in text.lines().enumerate() {
        let l = line.trim();
        if let Some(h) = l.strip_prefix('[') {
            let h = h.split(']').next().unwrap_or("");
            current = h.trim().replace(' ', "");
            continue;
        }
        if let Some((lhs, _)) = l.split_once('=') {
            let lhs = lhs.trim().trim_matches('"').trim_matches('\'');
            if current == table && lhs == name {
                return Some(k as u64 + 1);
            }
        }
    }
    None
}

/// What to write instead of one of kisstime's former key names (or another simulator's),
/// at the top level.
fn ball_hint(key: &str) -> Option<&'static str> {
    Some(match key {
        "radius" | "r" | "ball_radius" => "pooltool's name is `R`",
        "ball_mass" | "mass" => "pooltool's name is `m`",
        "M" => "`M` is the cue's mass: it belongs in the [cue] table (the ball's mass is `m`)",
        "mu_s" => "pooltool's name is `u_s`",
        "mu_r" => "pooltool's name is `u_r`",
        "mu_b" => "pooltool's name is `u_b`",
        "mu_sp" | "u_sp" => {
            "pooltool sets the spinning friction as `u_sp_proportionality` (u_sp = \
             u_sp_proportionality × R): give u_sp / R"
        }
        "cue_mass" => "pooltool's name is `M`, in the [cue] table",
        "cue_end_mass" | "end_mass" => "pooltool's name is `end_mass`, in the [cue] table",
        "gravity" => "pooltool's name is `g`",
        _ => return None,
    })
}

/// What to write instead, in the `[cue]` table.
fn cue_hint(key: &str) -> Option<&'static str> {
    Some(match key {
        "mass" | "m" | "cue_mass" => "pooltool's name is `M`",
        "cue_end_mass" => "pooltool's name is `end_mass`",
        "english_throttle" | "squirt_throttle" => {
            "not a CueSpecs field (pooltool's stick-ball model has it, and kisstime keeps \
             its default 1)"
        }
        "brand"
        | "length"
        | "tip_radius"
        | "butt_radius"
        | "shaft_radius_at_tip"
        | "shaft_radius_at_butt" => {
            "a CueSpecs field that pooltool's physics does not use (only its rendering \
             does): leave it out"
        }
        _ => return None,
    })
}

/// The simulator's parameters from `entries` (a physics file's top level, or a study's
/// `[physics]` table): pooltool's default for every key left out. `allow_cue` admits the
/// `[cue]` table (a table JSON's `ball_params` has none). Errors name `src`'s file and
/// the key (module docs).
pub fn physics_from_entries(
    entries: &[(String, PhysicsValue)],
    src: &PhysicsSource,
    allow_cue: bool,
) -> Result<SimParams, Error> {
    let known = format!(
        "{}{}",
        BALL_KEYS.join(", "),
        if allow_cue {
            format!(" and the table [{CUE_TABLE}] ({})", CUE_KEYS.join(", "))
        } else {
            String::new()
        }
    );
    let mut ball = [None::<f64>; BALL_KEYS.len()];
    let mut cue = [None::<f64>; CUE_KEYS.len()];
    let number = |key: &str, v: &PhysicsValue| match v {
        PhysicsValue::Num(x) => Ok(*x),
        other => Err(src.error(
            key,
            format!(
                "key `{}` is {}, it must be a number",
                src.full(key),
                other.kind()
            ),
        )),
    };
    for (key, value) in entries {
        if let Some(k) = BALL_KEYS.iter().position(|b| b == key) {
            ball[k] = Some(number(key, value)?);
        } else if allow_cue && key == CUE_TABLE {
            let PhysicsValue::Table(items) = value else {
                return Err(src.error(
                    key,
                    format!(
                        "key `{}` is {}, it must be a table of the cue's keys ({})",
                        src.full(key),
                        value.kind(),
                        CUE_KEYS.join(", ")
                    ),
                ));
            };
            for (ck, cv) in items {
                let full_key = format!("{CUE_TABLE}.{ck}");
                if let Some(k) = CUE_KEYS.iter().position(|c| c == ck) {
                    cue[k] = Some(number(&full_key, cv)?);
                } else {
                    let why = match cue_hint(ck) {
                        Some(h) => h.to_owned(),
                        None => format!(
                            "not one of pooltool 0.6.0's CueSpecs keys ({})",
                            CUE_KEYS.join(", ")
                        ),
                    };
                    return Err(src.error(
                        &full_key,
                        format!("unknown key `{}`: {why}", src.full(&full_key)),
                    ));
                }
            }
        } else {
            let why = match ball_hint(key) {
                Some(h) if !allow_cue && h.contains("[cue]") => {
                    format!("a cue parameter, which {} does not carry", src.file)
                }
                Some(h) => h.to_owned(),
                None => format!("not one of pooltool 0.6.0's keys ({known})"),
            };
            return Err(src.error(key, format!("unknown key `{}`: {why}", src.full(key))));
        }
    }
    let d = BallParams::default();
    let [m, r, u_s, u_r, u_sp_prop, u_b, e_b, e_c, f_c, g] = ball;
    let r = r.unwrap_or(d.r);
    let prop = u_sp_prop.unwrap_or(DEFAULT_U_SP_PROPORTIONALITY);
    let ball_params = BallParams {
        m: m.unwrap_or(d.m),
        r,
        u_s: u_s.unwrap_or(d.u_s),
        u_r: u_r.unwrap_or(d.u_r),
        // pooltool's property: u_sp = u_sp_proportionality * R (bit for bit the default's
        // expression when neither is given)
        u_sp: prop * r,
        u_b: u_b.unwrap_or(d.u_b),
        e_b: e_b.unwrap_or(d.e_b),
        e_c: e_c.unwrap_or(d.e_c),
        f_c: f_c.unwrap_or(d.f_c),
        g: g.unwrap_or(d.g),
    };
    let c = CueParams::default();
    let [cue_m, cue_end] = cue;
    let params = SimParams {
        ball: ball_params,
        cue: CueParams {
            mass: cue_m.unwrap_or(c.mass),
            end_mass: cue_end.unwrap_or(c.end_mass),
            ..c
        },
        resolver: ResolverParams::default(),
    };
    params
        .validate()
        .map_err(|e| range_error(e, &params, prop, src))?;
    Ok(params)
}

/// [`SimParams::validate`]'s error with the field named by its key.
fn range_error(e: SimError, p: &SimParams, prop: f64, src: &PhysicsSource) -> Error {
    let SimError::Param { name, value } = e else {
        return src.error("", format!("{}: {e}", src.file));
    };
    let (key, value, range) = match name {
        "u_sp" => ("u_sp_proportionality", prop, "finite and greater than 0"),
        "cue mass" => ("cue.M", value, "finite and greater than 0"),
        "cue end_mass" => ("cue.end_mass", value, "finite and greater than 0"),
        "e_b" | "e_c" => (name, value, "in (0, 1]"),
        "u_b" | "f_c" => (name, value, "finite and not negative"),
        "u_s * g" | "u_r * g" | "u_sp * g" => {
            let (a, av) = match name {
                "u_s * g" => ("u_s", p.ball.u_s),
                "u_r * g" => ("u_r", p.ball.u_r),
                _ => ("u_sp_proportionality", prop),
            };
            return src.error(
                a,
                format!(
                    "keys `{}` = {av} and `{}` = {}: the deceleration they give is {value}, it \
                     must be finite and greater than 0",
                    src.full(a),
                    src.full("g"),
                    p.ball.g
                ),
            );
        }
        other => (other, value, "finite and greater than 0"),
    };
    src.error(
        key,
        format!("key `{}` is {value}, it must be {range}", src.full(key)),
    )
}

/// The parameters of a physics file's TOML `text` (module docs); errors name `source`
/// as the file, the key and the line.
pub fn parse_physics_toml(text: &str, source: &str) -> Result<SimParams, Error> {
    physics_of_toml(text, source, true)
}

/// The parameters of TOML `text` that a program wrote from a mapping of pooltool's names
/// (Python's `physics={...}`, the cue's under `cue`): as [`parse_physics_toml`], but the
/// messages name `source` and the key without a line, which would mean nothing to the
/// mapping's author.
pub fn parse_physics_mapping(text: &str, source: &str) -> Result<SimParams, Error> {
    physics_of_toml(text, source, false)
}

fn physics_of_toml(text: &str, source: &str, lines: bool) -> Result<SimParams, Error> {
    let table: toml::Table = toml::from_str(text).map_err(|e| {
        let mut e = toml_error(&e, text, source);
        if let (Error::Input(ie), false) = (&mut e, lines) {
            ie.line = None;
        }
        e
    })?;
    let PhysicsValue::Table(entries) = PhysicsValue::from_toml_table(&table) else {
        unreachable!("a table converts to a table")
    };
    physics_from_entries(
        &entries,
        &PhysicsSource {
            file: source,
            prefix: "",
            toml_text: lines.then_some(text),
        },
        true,
    )
}

/// The parameters of the physics file at `path` ([`parse_physics_toml`]); a file that
/// cannot be read is an [`Error::Io`].
pub fn read_physics(path: &Path) -> Result<SimParams, Error> {
    let text = std::fs::read_to_string(path).map_err(|source| Error::Io {
        path: path.display().to_string(),
        source,
    })?;
    parse_physics_toml(&text, &path.display().to_string())
}

/// The physics of `--physics PATH` for a batch of tables `table_ids` (in its order): a
/// TOML file's one set, or a `.csv` file's set per table ([`parse_physics_csv`]: pooltool's
/// defaults with each table's row in place); pooltool's defaults without a path.
pub fn read_batch_physics(path: Option<&Path>, table_ids: &[i64]) -> Result<BatchPhysics, Error> {
    read_batch_physics_on(path, table_ids, "9ft")
}

/// [`read_batch_physics`] for tables `table_name` (a `--table` value): without a path, the
/// balls that table's game is played with
/// ([`crate::io::table_json::default_ball_params`]: snooker balls on `snooker`, carom balls
/// on `carom`, pool balls elsewhere), as pooltool's `BallParams.default(game_type)`. A
/// given file's keys fill the rest with pooltool's class defaults, as `BallParams(...)`
/// does.
pub fn read_batch_physics_on(
    path: Option<&Path>,
    table_ids: &[i64],
    table_name: &str,
) -> Result<BatchPhysics, Error> {
    let Some(path) = path else {
        return Ok(BatchPhysics::Shared(SimParams {
            ball: crate::io::table_json::default_ball_params(table_name),
            ..SimParams::default()
        }));
    };
    let is_csv = path
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("csv"));
    if !is_csv {
        return read_physics(path).map(BatchPhysics::Shared);
    }
    let source = path.display().to_string();
    let text = std::fs::read_to_string(path).map_err(|e| Error::Io {
        path: source.clone(),
        source: e,
    })?;
    let columns = parse_physics_csv(&text, &source)?;
    columns
        .for_tables(&[], table_ids, &source)
        .map(BatchPhysics::PerTable)
}

/// A batch's physics as read: one set, or one per table (owned; [`BatchPhysics::as_physics`]
/// lends it to the simulator).
#[derive(Clone, Debug, PartialEq)]
pub enum BatchPhysics {
    /// Every table with these parameters.
    Shared(SimParams),
    /// Table `k` (in the batch's order) with `[k]`.
    PerTable(Vec<SimParams>),
}

impl BatchPhysics {
    /// As the simulator takes it.
    pub fn as_physics(&self) -> crate::model::sim_params::Physics<'_> {
        match self {
            BatchPhysics::Shared(p) => crate::model::sim_params::Physics::Shared(*p),
            BatchPhysics::PerTable(all) => crate::model::sim_params::Physics::PerTable(all),
        }
    }
}

/// The parameters of the physics file at `path` ([`read_physics`]), or pooltool's
/// defaults ([`SimParams::default`]) when there is none: what `kisstime simulate
/// --physics` resolves to.
pub fn read_physics_or_default(path: Option<&Path>) -> Result<SimParams, Error> {
    path.map_or_else(|| Ok(SimParams::default()), read_physics)
}

/// The parameters of a JSON object's text with the keys of a physics file (the cue's
/// under `"cue"`): what Python's `physics={...}` passes. Errors name `source` and the key.
pub fn parse_physics_json(text: &str, source: &str) -> Result<SimParams, Error> {
    let value: serde_json::Value = serde_json::from_str(text).map_err(|e| {
        Error::from(
            InputError::new(format!("not a table of physics parameters: {e}")).in_file(source),
        )
    })?;
    let PhysicsValue::Table(entries) = PhysicsValue::from_json(&value) else {
        return Err(InputError::new(format!(
            "the physics parameters must be a table (a dict) of pooltool's keys, not {}",
            PhysicsValue::from_json(&value).kind()
        ))
        .in_file(source)
        .into());
    };
    physics_from_entries(
        &entries,
        &PhysicsSource {
            file: source,
            prefix: "",
            toml_text: None,
        },
        true,
    )
}

/// The ball parameters of a `ball_params` JSON object (a pooltool-exported table JSON's,
/// or a `.json` scenario's) under `prefix` (e.g. `"ball_params."`): pooltool's
/// `BallParams` keys ([`BALL_KEYS`]) plus, as pooltool's exports write them, `u_sp` (the
/// derived `u_sp_proportionality · R`, which must agree with it to 1e-12 relative) and a
/// `note` (ignored). Errors name `file` and the key.
pub fn ball_params_from_json(
    value: &serde_json::Value,
    file: &str,
    prefix: &str,
) -> Result<BallParams, Error> {
    let src = PhysicsSource {
        file,
        prefix,
        toml_text: None,
    };
    let PhysicsValue::Table(mut entries) = PhysicsValue::from_json(value) else {
        return Err(src.error(
            "",
            format!(
                "key `{}` is {}, it must be an object of pooltool's BallParams",
                prefix.trim_end_matches('.'),
                PhysicsValue::from_json(value).kind()
            ),
        ));
    };
    let mut u_sp = None;
    entries.retain(|(k, v)| match k.as_str() {
        "note" => false,
        "u_sp" => {
            u_sp = Some(v.clone());
            false
        }
        _ => true,
    });
    let p = physics_from_entries(&entries, &src, false)?.ball;
    if let Some(v) = u_sp {
        let PhysicsValue::Num(x) = v else {
            return Err(src.error(
                "u_sp",
                format!("key `{prefix}u_sp` is {}, it must be a number", v.kind()),
            ));
        };
        let agrees = (x - p.u_sp).abs() <= 1e-12 * p.u_sp.abs();
        if !agrees {
            return Err(src.error(
                "u_sp",
                format!(
                    "key `{prefix}u_sp` is {x}, but u_sp_proportionality × R is {}: pooltool \
                     derives u_sp from them",
                    p.u_sp
                ),
            ));
        }
    }
    Ok(p)
}

/// The `ball_params` of a pooltool-exported table JSON's text (the format of
/// `data/fullshots/table.json`), if it carries them ([`ball_params_from_json`]); errors
/// name `source` and the key.
pub fn table_json_ball_params(text: &str, source: &str) -> Result<Option<BallParams>, Error> {
    let value: serde_json::Value = serde_json::from_str(text).map_err(|e| {
        Error::from(
            InputError::new(format!("bad JSON: {e}"))
                .in_file(source)
                .at_line(e.line() as u64),
        )
    })?;
    match value.get("ball_params") {
        Some(bp) => ball_params_from_json(bp, source, "ball_params.").map(Some),
        None => Ok(None),
    }
}

/// [`table_json_ball_params`] of the file at `path`; an unreadable file is an
/// [`Error::Io`].
pub fn read_table_ball_params(path: &Path) -> Result<Option<BallParams>, Error> {
    let text = std::fs::read_to_string(path).map_err(|source| Error::Io {
        path: path.display().to_string(),
        source,
    })?;
    table_json_ball_params(&text, &path.display().to_string())
}

/// `p` as a physics file (module docs) that [`parse_physics_toml`] reads back to the same
/// parameters (floats written as the shortest text that reads back exactly; the resolver's
/// constants and the cue's throttles, which the file does not set, are left out).
/// `u_sp_proportionality` is written as `u_sp / R`, which reproduces `u_sp` to an ulp.
pub fn physics_toml(p: &SimParams) -> String {
    let b = &p.ball;
    let mut s = String::new();
    for (k, v) in BALL_KEYS.iter().zip([
        b.m,
        b.r,
        b.u_s,
        b.u_r,
        b.u_sp / b.r,
        b.u_b,
        b.e_b,
        b.e_c,
        b.f_c,
        b.g,
    ]) {
        s.push_str(&format!("{k} = {v:?}\n"));
    }
    s.push_str(&format!(
        "\n[{CUE_TABLE}]\nM = {:?}\nend_mass = {:?}\n",
        p.cue.mass, p.cue.end_mass
    ));
    s
}

/// A TOML syntax or schema error, located at its line, naming the offending text (shared
/// with the study's parser, [`crate::study::StudyConfig::parse`]).
pub(crate) fn toml_error(e: &toml::de::Error, text: &str, source: &str) -> Error {
    let mut message = e.message().trim().to_owned();
    let mut line = None;
    if let Some(span) = e.span() {
        let start = span.start.min(text.len());
        line = Some(text[..start].matches('\n').count() as u64 + 1);
        // name the offending text when the message does not (e.g. "duplicate key")
        let at = text
            .get(start..span.end.min(text.len()))
            .and_then(|t| t.lines().next())
            .unwrap_or("")
            .trim();
        if !at.is_empty() && at.len() <= 60 && !message.contains(at) {
            message = format!("{message} (at `{at}`)");
        }
        // and the key whose value it is, when the line assigns one
        let line_text = text[..start].rsplit('\n').next().unwrap_or("");
        if let Some((key, _)) = line_text.split_once('=') {
            let key = key.trim();
            if !key.is_empty() && !key.starts_with('[') && !message.contains(&format!("`{key}`")) {
                message = format!("key `{key}`: {message}");
            }
        }
    }
    let mut ie = InputError::new(message).in_file(source);
    if let Some(line) = line {
        ie = ie.at_line(line);
    }
    Error::from(ie)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn err(text: &str) -> String {
        parse_physics_toml(text, "p.toml").unwrap_err().to_string()
    }

    #[test]
    fn an_empty_file_is_pooltools_defaults_bit_for_bit() {
        assert_eq!(
            parse_physics_toml("", "p.toml").unwrap(),
            SimParams::default()
        );
        assert_eq!(
            parse_physics_json("{}", "physics").unwrap(),
            SimParams::default()
        );
    }

    #[test]
    fn every_key_is_read_under_pooltools_name() {
        let p = parse_physics_toml(
            "m = 0.2\nR = 0.03\nu_s = 0.17\nu_r = 0.008\nu_sp_proportionality = 0.38\n\
             u_b = 0.06\ne_b = 0.97\ne_c = 0.9\nf_c = 0.25\ng = 10\n\
             [cue]\nM = 0.6\nend_mass = 0.005\n",
            "p.toml",
        )
        .unwrap();
        let b = p.ball;
        assert_eq!(
            (b.m, b.r, b.u_s, b.u_r, b.u_b, b.e_b, b.e_c, b.f_c, b.g),
            (0.2, 0.03, 0.17, 0.008, 0.06, 0.97, 0.9, 0.25, 10.0)
        );
        assert_eq!(b.u_sp, 0.38 * 0.03);
        assert_eq!((p.cue.mass, p.cue.end_mass), (0.6, 0.005));
        assert_eq!(p.resolver, ResolverParams::default());
        // R alone scales u_sp with it, as pooltool's property does; end_mass stays
        let p = parse_physics_toml("R = 0.03\nm = 0.2", "p.toml").unwrap();
        assert_eq!(p.ball.u_sp, DEFAULT_U_SP_PROPORTIONALITY * 0.03);
        assert_eq!(p.cue, CueParams::default());
    }

    #[test]
    fn the_reference_sets_file_reads() {
        let dir = concat!(env!("CARGO_MANIFEST_DIR"), "/data/physics");
        let p = read_physics(&Path::new(dir).join("physics.toml")).unwrap();
        let d = BallParams::default();
        assert_eq!((p.ball.u_s, p.ball.u_r, p.ball.e_c), (0.17, 0.008, 0.9));
        assert_eq!((p.ball.m, p.ball.r, p.ball.g), (d.m, d.r, d.g));
        assert_eq!(p.ball.u_sp, 0.38 * d.r);
        // and the table JSON beside it carries the same ball parameters
        let t = read_table_ball_params(&Path::new(dir).join("table.json")).unwrap();
        assert_eq!(t, Some(p.ball));
        let full = concat!(env!("CARGO_MANIFEST_DIR"), "/data/fullshots/table.json");
        assert_eq!(
            read_table_ball_params(Path::new(full)).unwrap(),
            Some(BallParams::default())
        );
    }

    #[test]
    fn old_names_say_which_pooltool_name_to_use() {
        for (old, new) in [
            ("radius", "`R`"),
            ("ball_mass", "`m`"),
            ("mu_s", "`u_s`"),
            ("mu_r", "`u_r`"),
            ("mu_sp", "`u_sp_proportionality`"),
            ("u_sp", "`u_sp_proportionality`"),
            ("cue_mass", "`M`, in the [cue]"),
            ("cue_end_mass", "`end_mass`, in the [cue]"),
        ] {
            let e = err(&format!("u_s = 0.2\n{old} = 0.1\n"));
            assert!(
                e.contains("p.toml, line 2") && e.contains(&format!("`{old}`")) && e.contains(new),
                "{old}: {e}"
            );
        }
        let e = err("[cue]\nmass = 0.5\n");
        assert!(
            e.contains("`cue.mass`") && e.contains("`M`") && e.contains("line 2"),
            "{e}"
        );
        let e = err("[cue]\ntip_radius = 0.01\n");
        assert!(e.contains("does not use"), "{e}");
    }

    #[test]
    fn unknown_keys_and_wrong_types_name_file_line_and_key() {
        let e = err("R = 0.03\nfoo = 1\n");
        assert!(
            e.starts_with("p.toml, line 2: unknown key `foo`")
                && e.contains("u_sp_proportionality"),
            "{e}"
        );
        let e = err("R = \"big\"\n");
        assert!(
            e.contains("line 1") && e.contains("key `R` is a string"),
            "{e}"
        );
        let e = err("cue = 3\n");
        assert!(e.contains("key `cue` is a number"), "{e}");
        let e = err("R = \n");
        assert!(e.starts_with("p.toml, line 1"), "{e}");
        let e = parse_physics_json(r#"{"R": null}"#, "physics")
            .unwrap_err()
            .to_string();
        assert_eq!(e, "physics: key `R` is null, it must be a number");
        let e = parse_physics_json("[1]", "physics")
            .unwrap_err()
            .to_string();
        assert!(e.contains("must be a table"), "{e}");
    }

    #[test]
    fn a_mapping_is_named_without_lines() {
        let e = parse_physics_mapping("u_s = 0.2\nradius = 0.03\n", "physics")
            .unwrap_err()
            .to_string();
        assert_eq!(e, "physics: unknown key `radius`: pooltool's name is `R`");
        let e = parse_physics_mapping("g = = 1", "physics")
            .unwrap_err()
            .to_string();
        assert!(e.starts_with("physics: ") && !e.contains("line"), "{e}");
        let p = parse_physics_mapping("R = 0.03\ncue = { M = 0.5 }\n", "physics").unwrap();
        assert_eq!((p.ball.r, p.cue.mass), (0.03, 0.5));
    }

    #[test]
    fn out_of_range_values_name_the_key() {
        for (text, key, range) in [
            ("R = -0.03", "`R` is -0.03", "greater than 0"),
            ("m = 0", "`m` is 0", "greater than 0"),
            (
                "u_sp_proportionality = -1",
                "`u_sp_proportionality` is -1",
                "greater than 0",
            ),
            ("e_c = 1.5", "`e_c` is 1.5", "in (0, 1]"),
            ("f_c = -0.1", "`f_c` is -0.1", "not negative"),
            ("g = nan", "`g` is NaN", "greater than 0"),
            ("[cue]\nM = -1", "`cue.M` is -1", "greater than 0"),
            (
                "[cue]\nend_mass = inf",
                "`cue.end_mass` is inf",
                "greater than 0",
            ),
        ] {
            let e = err(text);
            assert!(
                e.starts_with("p.toml, line") && e.contains(key) && e.contains(range),
                "{text}: {e}"
            );
        }
        let e = err("u_s = 1e-200\ng = 1e-200");
        assert!(
            e.contains("`u_s`") && e.contains("`g`") && e.contains("deceleration"),
            "{e}"
        );
    }

    #[test]
    fn a_study_prefix_names_the_keys_in_their_table() {
        let text = "[physics]\nR = 0.03\nradius = 2\n";
        let t: toml::Table = toml::from_str(text).unwrap();
        let PhysicsValue::Table(entries) = PhysicsValue::from_toml(&t["physics"]) else {
            panic!()
        };
        let src = PhysicsSource {
            file: "s.toml",
            prefix: "physics.",
            toml_text: Some(text),
        };
        let e = physics_from_entries(&entries, &src, true)
            .unwrap_err()
            .to_string();
        assert!(
            e.starts_with("s.toml, line 3: unknown key `physics.radius`"),
            "{e}"
        );
    }

    #[test]
    fn table_json_ball_params_check_u_sp_and_refuse_cue_keys() {
        let bp = |s: &str| {
            table_json_ball_params(&format!(r#"{{"ball_params": {s}}}"#), "t.json")
                .map_err(|e| e.to_string())
        };
        assert_eq!(bp(r#"{"note": "x"}"#).unwrap(), Some(BallParams::default()));
        assert_eq!(table_json_ball_params("{}", "t.json").unwrap(), None);
        let e = bp(r#"{"u_sp": 0.5}"#).unwrap_err();
        assert!(e.contains("`ball_params.u_sp` is 0.5"), "{e}");
        let e = bp(r#"{"cue": {"M": 1}}"#).unwrap_err();
        assert!(e.contains("unknown key `ball_params.cue`"), "{e}");
        let e = bp(r#"{"radius": 0.03}"#).unwrap_err();
        assert!(e.contains("`R`"), "{e}");
    }

    #[test]
    fn a_written_file_reads_back() {
        for p in [
            SimParams::default(),
            parse_physics_toml("R = 0.03\nu_sp_proportionality = 0.38\n[cue]\nM = 0.5", "p")
                .unwrap(),
        ] {
            let q = parse_physics_toml(&physics_toml(&p), "p").unwrap();
            assert_eq!((q.ball.m, q.ball.r, q.cue), (p.ball.m, p.ball.r, p.cue));
            assert!((q.ball.u_sp - p.ball.u_sp).abs() <= 1e-18, "{q:?}");
        }
    }
}

/// Per-table physics as columns: one row per table (its id in `tables`), one column per
/// parameter (pooltool's names; the cue's as `cue.M`, `cue.end_mass`). Each table's
/// parameters are the base set's (a physics file, or pooltool's defaults) with its row's
/// values in place: what `kisstime simulate --physics FILE.csv` and Python's
/// `physics={"table": ids, "u_r": array, ...}` give.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct PhysicsColumns {
    /// The table id of each row.
    pub tables: Vec<i64>,
    /// Each parameter's name and its value per row.
    pub columns: Vec<(String, Vec<f64>)>,
    /// Each row's 1-based line in its file (empty where the rows did not come from one).
    pub lines: Vec<u64>,
}

impl PhysicsColumns {
    /// Every table's parameters, in the order of `table_ids` (a batch's tables): the base
    /// entries (a physics file's or mapping's top level; may be empty) with the table's row
    /// in place, read by [`physics_from_entries`], so every key and range is checked as in a
    /// physics file. Errors name `source`, the row's line where known, the table and the
    /// key: a table of the batch without a row, a row for a table not in it, a repeated
    /// table, an unknown column.
    pub fn for_tables(
        &self,
        base: &[(String, PhysicsValue)],
        table_ids: &[i64],
        source: &str,
    ) -> Result<Vec<SimParams>, Error> {
        let at_row = |row: usize, table: i64, msg: String| {
            let mut e = InputError::new(msg).in_file(source).at_table(table);
            if let Some(&line) = self.lines.get(row) {
                e = e.at_line(line);
            }
            Error::from(e)
        };
        let mut row_of = std::collections::HashMap::with_capacity(self.tables.len());
        for (row, &t) in self.tables.iter().enumerate() {
            if row_of.insert(t, row).is_some() {
                return Err(at_row(row, t, format!("table {t} has a second row")));
            }
        }
        let wanted: std::collections::HashSet<i64> = table_ids.iter().copied().collect();
        if let Some((row, &t)) = self
            .tables
            .iter()
            .enumerate()
            .find(|(_, t)| !wanted.contains(t))
        {
            return Err(at_row(row, t, format!("table {t} is not in the input")));
        }
        table_ids
            .iter()
            .map(|&t| {
                let Some(&row) = row_of.get(&t) else {
                    return Err(Error::from(
                        InputError::new(format!("no row for table {t}: every table needs one"))
                            .in_file(source)
                            .at_table(t),
                    ));
                };
                let mut entries: Vec<(String, PhysicsValue)> = base.to_vec();
                let mut cue: Vec<(String, PhysicsValue)> = Vec::new();
                for (name, values) in &self.columns {
                    let v = PhysicsValue::Num(values[row]);
                    match name.strip_prefix("cue.") {
                        Some(k) => cue.push((k.to_owned(), v)),
                        None => {
                            entries.retain(|(k, _)| k != name);
                            entries.push((name.clone(), v));
                        }
                    }
                }
                if !cue.is_empty() {
                    let mut table = match entries.iter().position(|(k, _)| k == CUE_TABLE) {
                        Some(i) => match entries.remove(i).1 {
                            PhysicsValue::Table(t) => t,
                            other => vec![("?".to_owned(), other)],
                        },
                        None => Vec::new(),
                    };
                    for (k, v) in cue {
                        table.retain(|(x, _)| *x != k);
                        table.push((k, v));
                    }
                    entries.push((CUE_TABLE.to_owned(), PhysicsValue::Table(table)));
                }
                let label = format!("{source} (table {t})");
                physics_from_entries(
                    &entries,
                    &PhysicsSource {
                        file: &label,
                        prefix: "",
                        toml_text: None,
                    },
                    true,
                )
                .map_err(|e| match e {
                    Error::Input(mut ie) => {
                        ie.table = Some(t);
                        ie.file = Some(source.to_owned());
                        if let Some(&line) = self.lines.get(row) {
                            ie.line = Some(line);
                        }
                        Error::Input(ie)
                    }
                    other => other,
                })
            })
            .collect()
    }
}

/// A per-table physics file (`kisstime simulate --physics FILE.csv`): a header `table,KEY,…`
/// (pooltool's names, the cue's as `cue.M`, `cue.end_mass`), then one row per table, its id
/// and numbers. Errors name the file, the line and the column.
pub fn parse_physics_csv(text: &str, source: &str) -> Result<PhysicsColumns, Error> {
    let err = |line: usize, msg: String| {
        Error::from(
            InputError::new(msg)
                .in_file(source)
                .at_line(line as u64 + 1),
        )
    };
    let mut lines = text
        .lines()
        .enumerate()
        .filter(|(_, l)| !l.trim().is_empty());
    let Some((h, header)) = lines.next() else {
        return Err(err(
            0,
            "empty: expected a header `table,KEY,...`".to_owned(),
        ));
    };
    let names: Vec<&str> = header.split(',').map(str::trim).collect();
    if names.first() != Some(&"table") || names.len() < 2 {
        return Err(err(
            h,
            "the header must be `table` then pooltool's parameter names (u_r, e_c, cue.M, ...)"
                .to_owned(),
        ));
    }
    let mut out = PhysicsColumns {
        columns: names[1..]
            .iter()
            .map(|n| ((*n).to_owned(), Vec::new()))
            .collect(),
        ..PhysicsColumns::default()
    };
    for (i, line) in lines {
        let fields: Vec<&str> = line.split(',').map(str::trim).collect();
        if fields.len() != names.len() {
            return Err(err(
                i,
                format!("{} fields, the header has {}", fields.len(), names.len()),
            ));
        }
        let table: i64 = fields[0]
            .parse()
            .map_err(|_| err(i, format!("table `{}` is not an integer id", fields[0])))?;
        for (c, f) in fields[1..].iter().enumerate() {
            let v: f64 = f.parse().map_err(|_| {
                err(
                    i,
                    format!("column `{}`: `{f}` is not a number", names[c + 1]),
                )
            })?;
            out.columns[c].1.push(v);
        }
        out.tables.push(table);
        out.lines.push(i as u64 + 1);
    }
    Ok(out)
}
