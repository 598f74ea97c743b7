//! Files meadow reads (a `--compare` document, a `--script`): regular files only, bounded in
//! size, and read only when the process has the memory to hold what they become. A FIFO, a
//! device (`/dev/zero`) or a directory is refused with exit 2 before a byte is read: opened
//! without blocking (`O_NONBLOCK`, so a FIFO with no writer cannot hang the open), then asked
//! what it is.

use std::io::Read;
use std::os::unix::fs::OpenOptionsExt;
use std::path::Path;

use crate::error::{quoted, Error, Result};

/// Read the regular file `path` (given as `flag`) as UTF-8 text of at most `most` bytes. What
/// reading and parsing it costs, `expansion` times its size (a parsed document is larger than
/// its text), must fit under the address-space limit (`address_space::check_headroom`): under a
/// tight `ulimit -v` the read ends with an error line, not an allocation abort.
pub fn read_text(path: &Path, flag: &str, most: u64, expansion: u64) -> Result<String> {
    let shown = || format!("{flag} {}", quoted(&path.display().to_string()));
    let file = std::fs::OpenOptions::new()
        .read(true)
        .custom_flags(libc::O_NONBLOCK)
        .open(path)
        .map_err(|e| Error::bad_input(format!("{}: {e}", shown())))?;
    let meta = file.metadata().map_err(|e| Error::bad_input(format!("{}: {e}", shown())))?;
    if !meta.is_file() {
        let kind = match meta.file_type() {
            t if t.is_dir() => "a directory",
            t if std::os::unix::fs::FileTypeExt::is_fifo(&t) => "a FIFO",
            t if std::os::unix::fs::FileTypeExt::is_char_device(&t) => "a character device",
            t if std::os::unix::fs::FileTypeExt::is_block_device(&t) => "a block device",
            _ => "not a regular file",
        };
        return Err(Error::bad_input(format!("{}: is {kind}; meadow reads regular files only", shown())));
    }
    let too_big = |bytes: u64| {
        Error::bad_input(format!(
            "{}: {} is over the {} meadow reads",
            shown(),
            crate::vk::device::format_bytes(bytes),
            crate::vk::device::format_bytes(most)
        ))
    };
    if meta.len() > most {
        return Err(too_big(meta.len()));
    }
    crate::vk::address_space::check_headroom(meta.len().saturating_mul(expansion), &format!("reading {}", shown()))?;
    let mut bytes = Vec::new();
    bytes
        .try_reserve_exact(meta.len() as usize + 1)
        .map_err(|_| Error::OutOfMemory { during: format!("reading {}", shown()), memory: "host" })?;
    // Bounded even if the file grows while it is read.
    file.take(most + 1).read_to_end(&mut bytes).map_err(|e| Error::bad_input(format!("{}: {e}", shown())))?;
    if bytes.len() as u64 > most {
        return Err(too_big(bytes.len() as u64));
    }
    String::from_utf8(bytes).map_err(|e| Error::bad_input(format!("{}: not UTF-8 text: {}", shown(), e.utf8_error())))
}
