//! Output files: atomic for regular files (a temporary file in the same folder, renamed
//! over the requested name only when complete), straight through for devices and FIFOs,
//! links followed; several outputs of one run renamed into place together; and the
//! clean-up an interrupted run needs.

use std::io::{Seek, SeekFrom, Write};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};

use crate::error::Error;

/// An I/O error while writing the output of [`write_output`], which names the output.
pub fn output_error(source: std::io::Error) -> Error {
    Error::Io {
        path: String::new(),
        source,
    }
}

/// An output being written: a writer that, where the output can be rewritten (a regular
/// file, memory), also rewrites its first bytes at the end — how a `.npy` file whose row
/// count is known only at the end gets its header without copying its rows.
pub trait Output: Write {
    /// Whether [`Output::rewrite_start`] can go back: true for a regular file and memory,
    /// false for a stream (standard output, a device, a FIFO).
    fn rewritable(&self) -> bool;

    /// Replaces the output's first `bytes.len()` bytes (already written) with `bytes` and
    /// leaves the position at the end; an error where the output is not
    /// [`Output::rewritable`].
    fn rewrite_start(&mut self, bytes: &[u8]) -> std::io::Result<()>;
}

impl Output for Vec<u8> {
    fn rewritable(&self) -> bool {
        true
    }

    fn rewrite_start(&mut self, bytes: &[u8]) -> std::io::Result<()> {
        match self.get_mut(..bytes.len()) {
            Some(start) => {
                start.copy_from_slice(bytes);
                Ok(())
            }
            None => Err(std::io::Error::other("rewriting more than was written")),
        }
    }
}

/// Where one output goes.
enum Sink {
    /// Standard output, buffered (64 KiB).
    Stdout(std::io::BufWriter<std::io::StdoutLock<'static>>),
    /// A device, a FIFO, a socket: straight through.
    Through(std::io::BufWriter<std::fs::File>),
    /// A regular file: a temporary file beside `target`, renamed over it when complete.
    File {
        w: std::io::BufWriter<std::fs::File>,
        tmp: tempfile::TempPath,
        target: PathBuf,
        pending: Pending,
    },
}

impl Write for Sink {
    fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
        match self {
            Sink::Stdout(w) => w.write(buf),
            Sink::Through(w) => w.write(buf),
            Sink::File { w, .. } => w.write(buf),
        }
    }

    fn write_all(&mut self, buf: &[u8]) -> std::io::Result<()> {
        match self {
            Sink::Stdout(w) => w.write_all(buf),
            Sink::Through(w) => w.write_all(buf),
            Sink::File { w, .. } => w.write_all(buf),
        }
    }

    fn flush(&mut self) -> std::io::Result<()> {
        match self {
            Sink::Stdout(w) => w.flush(),
            Sink::Through(w) => w.flush(),
            Sink::File { w, .. } => w.flush(),
        }
    }
}

impl Output for Sink {
    fn rewritable(&self) -> bool {
        matches!(self, Sink::File { .. })
    }

    fn rewrite_start(&mut self, bytes: &[u8]) -> std::io::Result<()> {
        match self {
            Sink::Stdout(_) | Sink::Through(_) => Err(std::io::Error::new(
                std::io::ErrorKind::Unsupported,
                "a stream cannot be rewritten",
            )),
            Sink::File { w, .. } => {
                // (the buffer is flushed by the seek)
                w.seek(SeekFrom::Start(0))?;
                w.write_all(bytes)?;
                w.seek(SeekFrom::End(0))?;
                Ok(())
            }
        }
    }
}

/// One output opened by [`write_outputs`]: its name for messages and where it goes.
struct Opened {
    name: String,
    sink: Sink,
}

/// A finished regular file, written and on the disk, waiting to be renamed into place.
struct Ready {
    name: String,
    tmp: tempfile::TempPath,
    target: PathBuf,
    pending: Pending,
}

impl Opened {
    /// Opens the output at `path` (standard output for `None` and `-`), as
    /// [`write_output`] describes.
    fn open(path: Option<&Path>) -> Result<Opened, Error> {
        let path = path.filter(|p| p.as_os_str() != "-");
        let name = path.map_or_else(|| "standard output".to_owned(), |p| p.display().to_string());
        let io = |source| Error::Io {
            path: name.clone(),
            source,
        };
        let Some(path) = path else {
            let w = std::io::BufWriter::with_capacity(1 << 16, std::io::stdout().lock());
            return Ok(Opened {
                sink: Sink::Stdout(w),
                name,
            });
        };
        // what the path reaches, links followed
        let target = match std::fs::metadata(path) {
            Ok(meta) if meta.is_file() => std::fs::canonicalize(path).map_err(io)?,
            Ok(meta) if meta.is_dir() => {
                return Err(io(std::io::Error::new(
                    std::io::ErrorKind::IsADirectory,
                    "is a folder, not a file",
                )));
            }
            Ok(_) => {
                // a device, a FIFO, a socket (also `/dev/stdout`): write through
                let file = std::fs::OpenOptions::new()
                    .write(true)
                    .open(path)
                    .map_err(io)?;
                return Ok(Opened {
                    sink: Sink::Through(std::io::BufWriter::new(file)),
                    name,
                });
            }
            // nothing there yet, or a link to nothing yet: create what it names
            Err(_) => resolve_links(path).map_err(io)?,
        };
        let dir = match target.parent() {
            Some(p) if !p.as_os_str().is_empty() => p,
            _ => Path::new("."),
        };
        let mut builder = tempfile::Builder::new();
        builder.prefix(".kisstime-");
        // an ordinary new file's permissions (0666 less the umask), not a temporary file's
        // 0600
        #[cfg(unix)]
        builder.permissions(std::os::unix::fs::PermissionsExt::from_mode(0o666));
        let (file, tmp) = builder.tempfile_in(dir).map_err(io)?.into_parts();
        let pending = Pending::register(&tmp);
        Ok(Opened {
            sink: Sink::File {
                w: std::io::BufWriter::new(file),
                tmp,
                target,
                pending,
            },
            name,
        })
    }

    /// Flushes what is buffered and, for a regular file, puts it on the disk: the file is
    /// then [`Ready`] to be renamed into place.
    fn finish(self) -> Result<Option<Ready>, Error> {
        let name = self.name;
        let io = |source| Error::Io {
            path: name.clone(),
            source,
        };
        match self.sink {
            Sink::Stdout(mut w) => w.flush().map_err(io).map(|()| None),
            Sink::Through(mut w) => w.flush().map_err(io).map(|()| None),
            Sink::File {
                w,
                tmp,
                target,
                pending,
            } => {
                let file = w.into_inner().map_err(|e| io(e.into_error()))?;
                file.sync_all().map_err(io)?;
                Ok(Some(Ready {
                    name,
                    tmp,
                    target,
                    pending,
                }))
            }
        }
    }

    /// Gives the output up after a failure: a temporary file is removed (the name it was
    /// for keeps what it had); what is still buffered for standard output (a header, the
    /// first rows) is dropped, not flushed: a run refused on its first table prints nothing
    /// there; what a device or FIFO already has stays.
    fn abandon(self) {
        match self.sink {
            Sink::Stdout(w) => drop(w.into_parts()),
            Sink::Through(w) => drop(w),
            Sink::File { w, tmp, .. } => {
                drop(w.into_parts());
                drop(tmp);
            }
        }
    }
}

/// Set once outputs have been renamed into place: an interrupted run then says so.
static COMMITTED: AtomicBool = AtomicBool::new(false);

/// Renames every finished file over its name, holding [`PENDING`]'s lock throughout: a
/// signal handler ([`remove_unfinished_outputs`]) sees all of them before the renames (and
/// removes them; the process then ends before any rename) or none.
fn commit(ready: Vec<Ready>) -> Result<(), Error> {
    let mut list = PENDING.lock().unwrap_or_else(|e| e.into_inner());
    let mut result = Ok(());
    for r in ready {
        if result.is_ok() {
            result = r.tmp.persist(&r.target).map_err(|e| Error::Io {
                path: r.name.clone(),
                source: e.error,
            });
            if result.is_ok() {
                COMMITTED.store(true, Ordering::SeqCst);
            }
        }
        // (a file not renamed is removed by its TempPath when dropped)
        let path = r.pending.take();
        list.retain(|p| p != &path);
    }
    result
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
///   a FIFO, a socket — is written straight through, never replaced; a folder is refused;
/// - standard output is buffered (64 KiB): when `body` fails before the buffer first fills
///   (bad input found in the first tables), nothing at all is printed, not even a header.
pub fn write_output(
    path: Option<&Path>,
    body: impl FnOnce(&mut dyn Output) -> Result<(), Error>,
) -> Result<(), Error> {
    let mut out = Opened::open(path)?;
    match body(&mut out.sink) {
        Ok(()) => {
            let ready = out.finish()?;
            commit(ready.into_iter().collect())
        }
        Err(e) => {
            let named = match e {
                Error::Io { path, source } if path.is_empty() => Error::Io {
                    path: out.name.clone(),
                    source,
                },
                other => other,
            };
            out.abandon();
            Err(named)
        }
    }
}

/// Writes several outputs of one run, as [`write_output`] writes one, and renames the
/// regular files among them into place together, only when `body` has finished them all:
/// a failure, or a signal, leaves none of them (each name keeps what it had), never some
/// complete and some not. Each entry of `paths` is `None` (no such output: `body` gets
/// `None` there) or `Some(path)`, where a path of `None` or `-` is standard output.
/// `body`'s errors are returned as they are: it names the output in them.
pub fn write_outputs<const N: usize>(
    paths: [Option<Option<&Path>>; N],
    body: impl FnOnce([Option<&mut dyn Output>; N]) -> Result<(), Error>,
) -> Result<(), Error> {
    let mut opened: [Option<Opened>; N] = [const { None }; N];
    for (slot, path) in opened.iter_mut().zip(paths) {
        if let Some(path) = path {
            match Opened::open(path) {
                Ok(o) => *slot = Some(o),
                Err(e) => {
                    opened.into_iter().flatten().for_each(Opened::abandon);
                    return Err(e);
                }
            }
        }
    }
    let result = body(
        opened
            .each_mut()
            .map(|o| o.as_mut().map(|o| &mut o.sink as &mut dyn Output)),
    );
    if let Err(e) = result {
        opened.into_iter().flatten().for_each(Opened::abandon);
        return Err(e);
    }
    let mut ready = Vec::new();
    let mut failed = None;
    for o in opened.into_iter().flatten() {
        if failed.is_some() {
            o.abandon();
            continue;
        }
        match o.finish() {
            Ok(r) => ready.extend(r),
            Err(e) => failed = Some(e),
        }
    }
    match failed {
        // (the finished files are removed as `ready` drops)
        Some(e) => Err(e),
        None => commit(ready),
    }
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
/// by `tempfile` on failure, or renamed on success by [`commit`], which takes it off the
/// list under the list's lock).
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
    /// The entry's path, leaving nothing for `drop` to do: for [`commit`], which takes
    /// entries off the list itself while it holds the list's lock.
    fn take(mut self) -> PathBuf {
        std::mem::take(&mut self.0)
    }
}

impl Drop for Pending {
    fn drop(&mut self) {
        if self.0.as_os_str().is_empty() {
            return;
        }
        if let Ok(mut list) = PENDING.lock() {
            list.retain(|p| p != &self.0);
        }
    }
}

/// Removes the temporary files of every [`write_output`] still in progress: for a signal
/// handler (Ctrl-C), which then ends the process, so that an interrupted run leaves
/// nothing behind, neither under the requested names nor beside them. The answer: whether
/// outputs had already been renamed into place, complete, before (the handler says so
/// instead of "nothing written").
pub fn remove_unfinished_outputs() -> bool {
    // try_lock, a few times: a handler must not wait for ever on a lock that another
    // thread holds for an instant (the renames of [`commit`])
    for _ in 0..100 {
        if let Ok(list) = PENDING.try_lock() {
            for path in list.iter() {
                let _ = std::fs::remove_file(path);
            }
            return COMMITTED.load(Ordering::SeqCst);
        }
        std::thread::sleep(std::time::Duration::from_millis(1));
    }
    COMMITTED.load(Ordering::SeqCst)
}
