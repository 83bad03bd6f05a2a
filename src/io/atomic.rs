//! Atomic output files: a temporary file in the same folder, renamed over the requested
//! name only when complete; and the clean-up an interrupted run needs.

use std::io::Write;
use std::path::Path;

use crate::error::Error;

/// An I/O error while writing the output of [`write_output`], which names the output.
pub fn output_error(source: std::io::Error) -> Error {
    Error::Io {
        path: String::new(),
        source,
    }
}

/// Writes the output of a command: to `path` atomically when given, else to standard
/// output. `body` writes through the writer it is handed and reports write failures with
/// [`output_error`]; they come back naming the output.
///
/// To a file, the content goes to a temporary file in the same folder, renamed over `path`
/// only when `body` succeeded and the data reached the disk. On any error nothing is left
/// under `path` (an earlier file there is kept as it was) and the temporary file is removed.
pub fn write_output(
    path: Option<&Path>,
    body: impl FnOnce(&mut dyn Write) -> Result<(), Error>,
) -> Result<(), Error> {
    let name = path.map_or_else(|| "standard output".to_owned(), |p| p.display().to_string());
    let named = |e: Error| match e {
        Error::Io { path, source } if path.is_empty() => Error::Io {
            path: name.clone(),
            source,
        },
        other => other,
    };
    let io = |source| Error::Io {
        path: name.clone(),
        source,
    };
    let Some(path) = path else {
        let stdout = std::io::stdout();
        let mut w = std::io::BufWriter::new(stdout.lock());
        body(&mut w).map_err(named)?;
        return w.flush().map_err(io);
    };
    let dir = match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p,
        _ => Path::new("."),
    };
    let mut builder = tempfile::Builder::new();
    builder.prefix(".kisstime-");
    // an ordinary new file's permissions (0666 less the umask), not a temporary file's 0600
    #[cfg(unix)]
    builder.permissions(std::os::unix::fs::PermissionsExt::from_mode(0o666));
    let tmp = builder.tempfile_in(dir).map_err(io)?;
    let pending = Pending::register(tmp.path());
    let mut w = std::io::BufWriter::new(tmp);
    body(&mut w).map_err(named)?;
    let tmp = w.into_inner().map_err(|e| io(e.into_error()))?;
    tmp.as_file().sync_all().map_err(io)?;
    tmp.persist(path).map_err(|e| io(e.error))?;
    drop(pending);
    Ok(())
}

/// Temporary files of [`write_output`] not yet renamed into place.
static PENDING: std::sync::Mutex<Vec<std::path::PathBuf>> = std::sync::Mutex::new(Vec::new());

/// One entry of [`PENDING`], removed from the list when dropped (the file itself is removed
/// by `tempfile` on failure, or renamed on success).
struct Pending(std::path::PathBuf);

impl Pending {
    fn register(path: &Path) -> Pending {
        if let Ok(mut list) = PENDING.lock() {
            list.push(path.to_owned());
        }
        Pending(path.to_owned())
    }
}

impl Drop for Pending {
    fn drop(&mut self) {
        if let Ok(mut list) = PENDING.lock() {
            list.retain(|p| p != &self.0);
        }
    }
}

/// Removes the temporary files of every [`write_output`] still in progress: for a signal
/// handler (Ctrl-C), which then ends the process, so that an interrupted run leaves
/// nothing behind, neither under the requested names nor beside them.
pub fn remove_unfinished_outputs() {
    // try_lock, a few times: a handler must not wait for ever on a lock that another
    // thread holds for an instant
    for _ in 0..100 {
        if let Ok(list) = PENDING.try_lock() {
            for path in list.iter() {
                let _ = std::fs::remove_file(path);
            }
            return;
        }
        std::thread::sleep(std::time::Duration::from_millis(1));
    }
}
