//! Files meadow writes are whole or absent: the bytes go to a temporary file next to the target,
//! are flushed to the disk (`sync_all`), and only then renamed into place; any failure removes
//! the temporary file and leaves the target as it was. A target that exists and is not a regular
//! file (a FIFO, a device node, a directory) is refused, before any work when checked up front.
//!
//! A command that writes several files (`bench`, `overhead`, `timing`) writes them as one set
//! ([`write_set`]): every file goes to its synced temporary first, and they are renamed into place
//! only when all were written; a failure or a signal before that leaves none of them. The output
//! directory is created by the set's first file, and removed again (with the parents it needed)
//! when the set fails. Temporaries have short names of their own (`.meadow-PID-N.tmp`), so an
//! output name as long as the file system takes has one too. Two outputs of one command that
//! name the same file are refused before any work ([`check_distinct`]).
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

use crate::error::{quoted, Error, Result};

/// A path as an error message quotes it (`error::quoted`: a 4000-byte path is cut in the middle).
pub fn shown(path: &Path) -> String {
    quoted(&path.display().to_string()).into_owned()
}

/// Refuse `path` when it exists and is not a regular file (or a link to one). `flag` names the
/// option in the message.
pub fn check_target(path: &Path, flag: &str) -> Result<()> {
    // `x.png/` names a directory: the file could never be created (and `x.png/..` is no name).
    let text = path.as_os_str().to_string_lossy();
    if text.ends_with(std::path::is_separator) || path.file_name().is_none() {
        return Err(Error::bad_input(format!("{flag} {}: names a directory, not a file", shown(path))));
    }
    match std::fs::metadata(path) {
        Ok(meta) if meta.is_dir() => Err(Error::bad_input(format!("{flag} {}: is a directory", shown(path)))),
        Ok(meta) if !meta.is_file() => {
            Err(Error::bad_input(format!("{flag} {}: exists and is not a regular file", shown(path))))
        }
        _ => Ok(()),
    }
}

/// Check that `path` (given as `flag`) can be written before doing any work: its directory exists
/// and it is a regular file or absent.
pub fn check_output(path: &Path, flag: &str) -> Result<()> {
    let parent = path.parent().filter(|p| !p.as_os_str().is_empty()).unwrap_or(Path::new("."));
    if !parent.is_dir() {
        return Err(Error::bad_input(format!("{flag} {}: directory {} does not exist", shown(path), shown(parent))));
    }
    check_target(path, flag)
}

/// A temporary name next to `path`, unique in this process, and never longer than a name meadow
/// itself makes: a 255-byte output name (the longest most file systems take) still has a
/// temporary the file system accepts.
fn temporary(path: &Path) -> PathBuf {
    static NEXT: AtomicU64 = AtomicU64::new(0);
    let n = NEXT.fetch_add(1, Ordering::Relaxed);
    path.with_file_name(format!(".meadow-{}-{n}.tmp", std::process::id()))
}

/// `path` as the file system resolves it: absolute, through every symbolic link of the part that
/// exists, with `.` and `..` of the part that does not exist yet applied by name. Two outputs
/// that resolve alike are the same file.
fn resolved(path: &Path) -> PathBuf {
    use std::path::Component;
    let absolute = match path.is_absolute() {
        true => path.to_path_buf(),
        false => std::env::current_dir().unwrap_or_default().join(path),
    };
    let components: Vec<Component> = absolute.components().collect();
    for exists in (1..=components.len()).rev() {
        let Ok(mut at) = components[..exists].iter().collect::<PathBuf>().canonicalize() else { continue };
        for component in &components[exists..] {
            match component {
                Component::ParentDir => {
                    at.pop();
                }
                Component::CurDir => {}
                other => at.push(other),
            }
        }
        return at;
    }
    absolute
}

/// Refuse two outputs of one command that name the same file, before any work: the second write
/// would replace the first, and both would be reported written. Paths are compared resolved
/// ([`resolved`]), and by device and inode when the file exists (a hard link is the same file).
/// `outputs` are (flag, path); a set's members are `--out` with the set's names ([`set_members`]).
pub fn check_distinct<'a>(outputs: impl IntoIterator<Item = (&'a str, PathBuf)>) -> Result<()> {
    use std::os::unix::fs::MetadataExt;
    let identity = |path: &Path| std::fs::metadata(path).ok().map(|m| (m.dev(), m.ino()));
    // (flag, path as given, resolved, device and inode if it exists)
    type Seen<'a> = (&'a str, PathBuf, PathBuf, Option<(u64, u64)>);
    let mut seen: Vec<Seen> = Vec::new();
    for (flag, path) in outputs {
        let (at, id) = (resolved(&path), identity(&path));
        let same = seen.iter().find(|(_, _, a, i)| *a == at || (id.is_some() && *i == id));
        if let Some((first, given, ..)) = same {
            return Err(Error::bad_input(format!(
                "{first} {} and {flag} {} name the same file: give each output its own",
                shown(given),
                shown(&path)
            )));
        }
        seen.push((flag, path, at, id));
    }
    Ok(())
}

/// The files of a set written into `dir`, as [`check_distinct`] takes them.
pub fn set_members<'a>(dir: &'a Path, files: &'a [&'a str]) -> impl Iterator<Item = (&'static str, PathBuf)> + 'a {
    files.iter().map(move |f| ("--out", dir.join(f)))
}

/// Before any work: refuse an output directory that exists and is not a directory (the set
/// could never be written into it), and each file of the set that exists and is not a regular
/// file.
pub fn check_set(dir: &Path, files: &[&str]) -> Result<()> {
    if std::fs::metadata(dir).is_ok_and(|m| !m.is_dir()) {
        return Err(Error::bad_input(format!("--out {}: exists and is not a directory", shown(dir))));
    }
    files.iter().try_for_each(|f| check_target(&dir.join(f), "--out"))
}

/// The set being written on this thread: its directory, the directories its first file needed
/// (outermost first; removed again when the set fails), and the (temporary, target) pairs
/// written so far, renamed at its end.
struct Staged {
    dir: PathBuf,
    created: Vec<PathBuf>,
    files: Vec<(PathBuf, PathBuf)>,
}

thread_local! {
    /// Inside [`write_set`]: what the set wrote so far.
    static STAGED: RefCell<Option<Staged>> = const { RefCell::new(None) };
}

/// Create `dir` with its missing parents; returns those it created, outermost first.
fn create_dirs(dir: &Path) -> Result<Vec<PathBuf>> {
    let missing: Vec<PathBuf> =
        dir.ancestors().take_while(|d| !d.as_os_str().is_empty() && !d.exists()).map(Path::to_path_buf).collect();
    std::fs::create_dir_all(dir).map_err(|source| Error::Io { path: dir.display().to_string(), source })?;
    Ok(missing.into_iter().rev().collect())
}

/// Run `work`, which writes files through [`write_atomically`], and publish what it wrote as one
/// set: renamed into place only if `work` succeeds and no signal came (`interrupt`), every
/// temporary removed otherwise. `dir`, the set's directory, is created when the first file is
/// written (a run refused or stopped before leaves no empty folder), and removed again, with the
/// parents it needed, if the set fails.
pub fn write_set<T>(dir: &Path, work: impl FnOnce() -> Result<T>) -> Result<T> {
    let set = Staged { dir: dir.to_path_buf(), created: Vec::new(), files: Vec::new() };
    STAGED.with(|s| *s.borrow_mut() = Some(set));
    let result = work();
    let staged = STAGED.with(|s| s.borrow_mut().take()).expect("staged above");
    let published = result.and_then(|value| {
        super::interrupt::check()?;
        publish(&staged.files).map(|()| value)
    });
    if published.is_err() {
        for (tmp, _) in &staged.files {
            let _ = std::fs::remove_file(tmp);
        }
        for dir in staged.created.iter().rev() {
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
/// the rename waits for the set. A signal that came while the bytes were written (`interrupt`)
/// publishes nothing: [`Error::Interrupted`].
pub fn write_atomically(path: &Path, bytes: &[u8]) -> Result<()> {
    check_target(path, "output")?;
    let io = |source: std::io::Error| Error::Io { path: path.display().to_string(), source };
    // A set's directory is made by its first file.
    let set_dir = STAGED.with(|s| s.borrow().as_ref().map(|set| set.dir.clone()));
    let in_set = set_dir.is_some_and(|dir| path.starts_with(dir));
    if let Some(parent) = path.parent().filter(|p| in_set && !p.as_os_str().is_empty() && !p.exists()) {
        let created = create_dirs(parent)?;
        STAGED.with(|s| {
            if let Some(set) = s.borrow_mut().as_mut() {
                set.created.extend(created);
            }
        });
    }
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
        file.sync_all()
    })()
    .map_err(io)
    .and_then(|()| super::interrupt::check())
    .and_then(|()| {
        let pair = (tmp.clone(), path.to_path_buf());
        let staged = STAGED.with(|s| s.borrow_mut().as_mut().map(|set| set.files.push(pair)));
        match staged {
            Some(()) => Ok(()),
            None => std::fs::rename(&tmp, path).map_err(io),
        }
    });
    if written.is_err() {
        let _ = std::fs::remove_file(&tmp);
    }
    written
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
    let (nth, sync) = crate::vk::fault::write_failure()?;
    (nth == n).then_some(if sync { Stage::Sync } else { Stage::Write })
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
