//! Errors. Bad user data is an [`Error::Input`] or [`Error::Param`] (the CLI exits with
//! code 2); failing to read or write a file is an [`Error::Io`] (exit code 1). The library
//! never panics on user data.

use std::fmt;

/// Everything that can go wrong in this crate.
#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// Bad input data: the message names the file, line (or row), table and ball where known.
    #[error("{0}")]
    Input(#[from] InputError),
    /// A physical parameter that is not finite and positive.
    #[error("invalid parameter {name} = {value}: it must be finite and greater than 0")]
    Param {
        /// The parameter's name (`radius`, `mu_s`, `mu_r`, `mu_sp`, `g`).
        name: &'static str,
        /// The value given.
        value: f64,
    },
    /// No usable GPU: no adapter, or not the precision asked for. The `auto` backend falls
    /// back to the CPU on this error; the `gpu` backend reports it.
    #[error("{0}")]
    GpuUnavailable(String),
    /// A GPU operation failed (device lost, dispatch or readback error). The `auto` backend
    /// redoes the batch on the CPU; the `gpu` backend reports it.
    #[error("GPU error: {0}")]
    Gpu(String),
    /// A combination the crate does not offer (e.g. the CPU backend in f32).
    #[error("{0}")]
    Unsupported(String),
    /// The input asks for more than this machine can hold, or more than the crate allows
    /// (see [`crate::limits`]); refused before allocating.
    #[error("{0}")]
    TooLarge(String),
    /// Reading or writing a file failed.
    #[error("{path}: {source}")]
    Io {
        /// The file.
        path: String,
        /// What the operating system said.
        #[source]
        source: std::io::Error,
    },
}

impl Error {
    /// Whether the error is the user's data (input or parameters) rather than the system.
    pub fn is_bad_input(&self) -> bool {
        matches!(
            self,
            Error::Input(_) | Error::Param { .. } | Error::Unsupported(_) | Error::TooLarge(_)
        )
    }
}

/// Bad input data, located as precisely as is known.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct InputError {
    /// The file, when the data came from one.
    pub file: Option<String>,
    /// The 1-based line in that file (text files).
    pub line: Option<u64>,
    /// The 0-based row index in that file (array files, `.npy`: the row `a[row]`).
    pub row: Option<u64>,
    /// The table id.
    pub table: Option<i64>,
    /// The ball id.
    pub ball: Option<i64>,
    /// What is wrong.
    pub message: String,
}

impl InputError {
    /// An error with only a message; add the location with the `at_*` builders.
    pub fn new(message: impl Into<String>) -> InputError {
        InputError {
            message: message.into(),
            ..InputError::default()
        }
    }

    /// Sets the file.
    pub fn in_file(mut self, file: impl Into<String>) -> InputError {
        self.file = Some(file.into());
        self
    }

    /// Sets the line.
    pub fn at_line(mut self, line: u64) -> InputError {
        self.line = Some(line);
        self
    }

    /// Sets the row index (array files).
    pub fn at_row(mut self, row: u64) -> InputError {
        self.row = Some(row);
        self
    }

    /// Sets the table.
    pub fn at_table(mut self, table: i64) -> InputError {
        self.table = Some(table);
        self
    }

    /// Sets the ball.
    pub fn at_ball(mut self, ball: i64) -> InputError {
        self.ball = Some(ball);
        self
    }

    /// Sets the message (an error located first, worded after).
    pub fn with_message(mut self, message: impl Into<String>) -> InputError {
        self.message = message.into();
        self
    }
}

impl fmt::Display for InputError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let mut parts = Vec::new();
        if let Some(file) = &self.file {
            parts.push(file.clone());
        }
        if let Some(line) = self.line {
            parts.push(format!("line {line}"));
        }
        if let Some(row) = self.row {
            parts.push(format!("row {row}"));
        }
        if let Some(table) = self.table {
            parts.push(format!("table {table}"));
        }
        if let Some(ball) = self.ball {
            parts.push(format!("ball {ball}"));
        }
        if parts.is_empty() {
            f.write_str(&self.message)
        } else {
            write!(f, "{}: {}", parts.join(", "), self.message)
        }
    }
}

impl std::error::Error for InputError {}

/// What went wrong in the simulator ([`crate::simulate`]) or its inputs (tables, balls,
/// strikes, reference-set files), naming the offending item. Nothing there panics on user
/// data; it returns one of these, which converts into [`Error::Input`].
#[derive(Debug, thiserror::Error)]
pub enum SimError {
    /// A parameter out of range (its name and value).
    #[error("parameter {name} = {value} is out of range")]
    Param {
        /// The field's name.
        name: &'static str,
        /// Its value.
        value: f64,
    },
    /// A table description that cannot be used.
    #[error("table: {0}")]
    Table(String),
    /// A ball that cannot be simulated (index and reason).
    #[error("ball {index}: {reason}")]
    Ball {
        /// The ball's index in the table.
        index: usize,
        /// What is wrong with it.
        reason: String,
    },
    /// Two balls that overlap (their indices in the table, `first < second`, and how deep
    /// in m), found by [`crate::simulate::check_layout`]: by more than 10 µm at rest, or
    /// 0.1 mm where either moves.
    #[error(
        "balls {first} and {second} overlap by {depth:e} m (more than 10 µm at rest, 0.1 mm \
         where either moves)"
    )]
    Overlap {
        /// The first ball's index.
        first: usize,
        /// The second ball's index.
        second: usize,
        /// 2R minus the distance of their centres, m.
        depth: f64,
    },
    /// A cue strike that cannot be resolved.
    #[error("strike: {0}")]
    Strike(String),
    /// A shot-set file that cannot be read (file, line, reason).
    #[error("{file}:{line}: {reason}")]
    File {
        /// The file's path.
        file: String,
        /// The 1-based line (0 when the whole file is concerned).
        line: usize,
        /// What is wrong.
        reason: String,
    },
}

impl From<SimError> for Error {
    fn from(e: SimError) -> Error {
        Error::Input(InputError::new(e.to_string()))
    }
}
