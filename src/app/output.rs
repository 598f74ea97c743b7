//! Files meadow writes are whole or absent: the bytes go to a temporary file next to the target,
//! are flushed to the disk (`sync_all`), and only then renamed into place; any failure removes
//! the temporary file and leaves the target as it was. A target that exists and is not a regular
//! file (a FIFO, a device node, a directory) is refused, before any work when checked up front.
//!
//! A command that writes several files (`bench`, `overhead`, `timing`) writes them as one set
//! ([`write_set`]): every file goes to its synced temporary first, and they are renamed into place
//! only when all were written; a failure or Ctrl-C before that leaves none of them, and removes
//! the output directory if the set created it.
//!
//! `MEADOW_INJECT_WRITE_FAILURE=N` makes the N-th file the process writes (from 1) fail half-way,
//! as a full disk would (for the tests: a full filesystem cannot be mounted everywhere the tests
//! run); N past the first file of a set fails the set after some of it was written.
//! `MEADOW_INJECT_WRITE_FAILURE=N:sync` writes all of the N-th file and fails its `sync_all`, as a
//! disk that fills while the page cache is written back does.

use std::cell::RefCell;
use std::io::Write;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};

use crate::error::{Error, Result};

/// Refuse `path` when it exists and is not a regular file (or a link to one). `flag` names the
/// option in the message.
pub fn check_target(path: &Path, flag: &str) -> Result<()> {
    // `x.png/` names a directory: the file could never be created (and `x.png/..` is no name).
    let text = path.as_os_str().to_string_lossy();
    if text.ends_with(std::path::is_separator) || path.file_name().is_none() {
        return Err(Error::bad_input(format!("{flag} {}: names a directory, not a file", path.display())));
    }
    match std::fs::metadata(path) {
        Ok(meta) if meta.is_dir() => Err(Error::bad_input(format!("{flag} {}: is a directory", path.display()))),
        Ok(meta) if !meta.is_file() => {
            Err(Error::bad_input(format!("{flag} {}: exists and is not a regular file", path.display())))
        }
        _ => Ok(()),
    }
}

/// Check that `path` (given as `flag`) can be written before doing any work: its directory exists
/// and it is a regular file or absent.
pub fn check_output(path: &Path, flag: &str) -> Result<()> {
    let parent = path.parent().filter(|p| !p.as_os_str().is_empty()).unwrap_or(Path::new("."));
    if !parent.is_dir() {
        return Err(Error::bad_input(format!(
            "{flag} {}: directory {} does not exist",
            path.display(),
            parent.display()
        )));
    }
    check_target(path, flag)
}

/// A temporary name next to `path`, unique in this process.
fn temporary(path: &Path) -> PathBuf {
    static NEXT: AtomicU64 = AtomicU64::new(0);
    let name = path.file_name().map_or_else(|| "meadow".into(), |n| n.to_string_lossy().into_owned());
    let n = NEXT.fetch_add(1, Ordering::Relaxed);
    path.with_file_name(format!(".{name}.{}.{n}.tmp", std::process::id()))
}

thread_local! {
    /// Inside [`write_set`]: the (temporary, target) pairs written so far, renamed at its end.
    static STAGED: RefCell<Option<Vec<(PathBuf, PathBuf)>>> = const { RefCell::new(None) };
}

/// Run `work`, which writes files through [`write_atomically`], and publish what it wrote as one
/// set: renamed into place only if `work` succeeds, every temporary removed otherwise. `dir`, the
/// set's directory, is created first if missing, and removed again (when empty) if the set fails.
pub fn write_set<T>(dir: &Path, work: impl FnOnce() -> Result<T>) -> Result<T> {
    let created = !dir.exists();
    std::fs::create_dir_all(dir).map_err(|source| Error::Io { path: dir.display().to_string(), source })?;
    STAGED.with(|s| *s.borrow_mut() = Some(Vec::new()));
    let result = work();
    let staged = STAGED.with(|s| s.borrow_mut().take()).unwrap_or_default();
    let published = result.and_then(|value| publish(&staged).map(|()| value));
    if published.is_err() {
        for (tmp, _) in &staged {
            let _ = std::fs::remove_file(tmp);
        }
        if created {
            let _ = std::fs::remove_dir(dir);
        }
    }
    published
}

/// Rename every staged file into place; if one fails, the ones already renamed are removed (a
/// set is whole or absent).
fn publish(staged: &[(PathBuf, PathBuf)]) -> Result<()> {
    for (i, (tmp, target)) in staged.iter().enumerate() {
        if let Err(source) = std::fs::rename(tmp, target) {
            for (_, done) in &staged[..i] {
                let _ = std::fs::remove_file(done);
            }
            return Err(Error::Io { path: target.display().to_string(), source });
        }
    }
    Ok(())
}

/// Write `bytes` to `path` whole or not at all (see the module comment); inside [`write_set`],
/// the rename waits for the set.
pub fn write_atomically(path: &Path, bytes: &[u8]) -> Result<()> {
    check_target(path, "output")?;
    let io = |source: std::io::Error| Error::Io { path: path.display().to_string(), source };
    let tmp = temporary(path);
    let written = (|| {
        let mut file = std::fs::OpenOptions::new().write(true).create_new(true).open(&tmp)?;
        let injected = injected_failure();
        if injected == Some(Stage::Write) {
            file.write_all(&bytes[..bytes.len() / 2])?;
            return Err(std::io::Error::new(std::io::ErrorKind::StorageFull, "no space left (injected)"));
        }
        file.write_all(bytes)?;
        file.flush()?;
        if injected == Some(Stage::Sync) {
            return Err(std::io::Error::new(std::io::ErrorKind::StorageFull, "no space left at sync (injected)"));
        }
        file.sync_all()?;
        let staged = STAGED.with(|s| s.borrow_mut().as_mut().map(|set| set.push((tmp.clone(), path.to_path_buf()))));
        match staged {
            Some(()) => Ok(()),
            None => std::fs::rename(&tmp, path),
        }
    })();
    if written.is_err() {
        let _ = std::fs::remove_file(&tmp);
    }
    written.map_err(io)
}

/// Where an injected write failure strikes.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Stage {
    /// Half-way through the bytes.
    Write,
    /// At `sync_all`, after every byte was written and flushed.
    Sync,
}

/// Whether this write is the one `MEADOW_INJECT_WRITE_FAILURE` makes fail, and where.
fn injected_failure() -> Option<Stage> {
    static WRITES: AtomicU64 = AtomicU64::new(0);
    let n = WRITES.fetch_add(1, Ordering::Relaxed) + 1;
    let value = std::env::var("MEADOW_INJECT_WRITE_FAILURE").ok()?;
    let (nth, stage) = match value.strip_suffix(":sync") {
        Some(nth) => (nth, Stage::Sync),
        None => (value.as_str(), Stage::Write),
    };
    (nth.parse::<u64>().ok()? == n).then_some(stage)
}

/// Encode an image as PNG in memory (so that every byte of it goes through `write_atomically`).
pub fn encode_png<P, C>(image: &image::ImageBuffer<P, C>) -> Result<Vec<u8>>
where
    P: image::PixelWithColorType,
    [P::Subpixel]: image::EncodableLayout,
    C: std::ops::Deref<Target = [P::Subpixel]>,
{
    let mut bytes = Vec::new();
    image
        .write_to(&mut std::io::Cursor::new(&mut bytes), image::ImageFormat::Png)
        .map_err(|e| Error::Io { path: "PNG encoder".into(), source: std::io::Error::other(e.to_string()) })?;
    Ok(bytes)
}
