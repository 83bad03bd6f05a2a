//! Output files: atomic for regular files (a temporary file in the same folder, renamed
//! over the requested name only when complete), straight through for devices and FIFOs,
//! links followed; and the clean-up an interrupted run needs.

use std::io::Write;
use std::path::{Path, PathBuf};

use crate::error::Error;

/// An I/O error while writing the output of [`write_output`], which names the output.
pub fn output_error(source: std::io::Error) -> Error {
    Error::Io {
        path: String::new(),
        source,
    }
}

/// Writes the output of a command: to `path` when given, else (and for `-`) to standard
/// output. `body` writes through the writer it is handed and reports write failures with
/// [`output_error`]; they come back naming the output.
///
/// Nothing the user did not name is touched:
/// - a symbolic link is followed to what it points at (the link itself stays), to any
///   depth;
/// - a regular file, or a path that does not exist yet, is written atomically: the content
///   goes to a temporary file beside it, renamed over it only when `body` succeeded and the
///   data reached the disk. On any error nothing is left under that name (an earlier file
///   there is kept as it was) and the temporary file is removed;
/// - anything else that exists — a character device such as `/dev/null` or `/dev/stdout`,
///   a FIFO, a socket — is written straight through, never replaced;
/// - standard output is buffered (64 KiB): when `body` fails before the buffer first fills
///   (bad input found in the first tables), nothing at all is printed, not even a header.
pub fn write_output(
    path: Option<&Path>,
    body: impl FnOnce(&mut dyn Write) -> Result<(), Error>,
) -> Result<(), Error> {
    let path = path.filter(|p| p.as_os_str() != "-");
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
        let mut w = std::io::BufWriter::with_capacity(1 << 16, stdout.lock());
        if let Err(e) = body(&mut w) {
            // what is still buffered (a header, the first rows) is dropped, not flushed:
            // a run refused on its first table prints nothing on standard output
            drop(w.into_parts());
            return Err(named(e));
        }
        return w.flush().map_err(io);
    };
    // what the path reaches, links followed
    let target = match std::fs::metadata(path) {
        Ok(meta) if meta.is_file() => std::fs::canonicalize(path).map_err(io)?,
        Ok(meta) if !meta.is_dir() => {
            // a device, a FIFO, a socket (also `/dev/stdout`): write through
            let file = std::fs::OpenOptions::new()
                .write(true)
                .open(path)
                .map_err(io)?;
            let mut w = std::io::BufWriter::new(file);
            body(&mut w).map_err(named)?;
            return w.flush().map_err(io);
        }
        // a folder: the rename below fails and says so
        Ok(_) => path.to_path_buf(),
        // nothing there yet, or a link to nothing yet: create what it names
        Err(_) => resolve_links(path).map_err(io)?,
    };
    let dir = match target.parent() {
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
    // through the file itself: an error names the output, not the temporary file (which
    // is removed)
    let mut w = std::io::BufWriter::new(tmp.as_file());
    body(&mut w).map_err(named)?;
    w.flush().map_err(io)?;
    drop(w);
    tmp.as_file().sync_all().map_err(io)?;
    pending.persist(tmp, &target).map_err(io)
}

/// The most symbolic links followed for one output path (as the kernel's `ELOOP` limit).
const MAX_LINKS: usize = 40;

/// `path` with the symbolic links it names followed, to any depth, for a path that does not
/// exist yet: a link to a missing file resolves to that file (the output is created there,
/// the link stays). A relative link is relative to the link's folder.
fn resolve_links(path: &Path) -> std::io::Result<PathBuf> {
    let mut current = path.to_path_buf();
    for _ in 0..MAX_LINKS {
        match std::fs::symlink_metadata(&current) {
            Ok(meta) if meta.file_type().is_symlink() => {
                let to = std::fs::read_link(&current)?;
                current = match current.parent() {
                    Some(dir) if to.is_relative() => dir.join(to),
                    _ => to,
                };
            }
            _ => return Ok(current),
        }
    }
    Err(std::io::Error::other(format!(
        "more than {MAX_LINKS} symbolic links in a row"
    )))
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

impl Pending {
    /// Renames `tmp` over `target` and takes it off the list, holding the list's lock
    /// throughout: a signal handler ([`remove_unfinished_outputs`]) sees the file either
    /// before the rename (and removes it; the process then ends before the rename) or not
    /// at all.
    fn persist(self, tmp: tempfile::NamedTempFile, target: &Path) -> std::io::Result<()> {
        let mut list = PENDING.lock().unwrap_or_else(|e| e.into_inner());
        let done = tmp.persist(target).map(|_| ()).map_err(|e| e.error);
        list.retain(|p| p != &self.0);
        drop(list);
        // (Drop then finds the entry gone)
        done
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
