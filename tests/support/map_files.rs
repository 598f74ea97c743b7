//! Map files for the tests of `--heightmap` and `--cover` (tests/heightmap.rs, tests/cover.rs):
//! PNGs written chunk by chunk (a header the image crate would not write), and `meadow render`
//! runs that must be refused in one line.

#![allow(dead_code)] // each test crate that includes it uses a different subset

use crate::support::{self, meadow, scratch, transcript};

/// Run `meadow render` with `args` (and a device and an output) in a fresh scratch directory;
/// returns the output and whether a picture was written.
pub fn render_cli(case: &str, args: &[&str]) -> (std::process::Output, bool) {
    let dir = scratch(&format!("map-{case}"));
    let out = dir.join("out.png");
    let mut cmd = meadow();
    cmd.arg("render").args(args).args(["--size", "32x32", "--device", support::DEVICE]);
    if !args.contains(&"--field") {
        cmd.args(["--blades", "500"]);
    }
    cmd.arg("--out");
    let output = cmd.arg(&out).current_dir(&dir).output().expect("run meadow");
    (output, out.exists())
}

/// Refused in one line, exit 2, nothing written, naming `why`.
pub fn refused(case: &str, args: &[&str], why: &str) {
    let (output, written) = render_cli(case, args);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(2), "{case}: {}", transcript(&output));
    assert_eq!(stderr.lines().count(), 1, "{case}: {}", transcript(&output));
    assert!(stderr.starts_with("error: ") && stderr.contains(why), "{case}: {stderr}");
    assert!(!stderr.contains("panicked") && !written, "{case}: {}", transcript(&output));
}

/// A PNG written chunk by chunk: `ihdr` (13 bytes), optional palette, the raw scanlines (each
/// led by its filter byte 0) in a zlib stream of stored blocks.
pub fn png(ihdr: [u8; 13], palette: Option<&[u8]>, scanlines: &[u8]) -> Vec<u8> {
    fn crc32(bytes: &[u8]) -> u32 {
        let mut crc = 0xffff_ffffu32;
        for &b in bytes {
            crc ^= u32::from(b);
            for _ in 0..8 {
                crc = if crc & 1 != 0 { (crc >> 1) ^ 0xedb8_8320 } else { crc >> 1 };
            }
        }
        !crc
    }
    fn chunk(out: &mut Vec<u8>, kind: &[u8; 4], data: &[u8]) {
        out.extend((data.len() as u32).to_be_bytes());
        let mut body = kind.to_vec();
        body.extend_from_slice(data);
        out.extend_from_slice(&body);
        out.extend(crc32(&body).to_be_bytes());
    }
    let mut zlib = vec![0x78, 0x01];
    let blocks: Vec<&[u8]> = scanlines.chunks(65_535).collect();
    for (i, block) in blocks.iter().enumerate() {
        zlib.push(u8::from(i + 1 == blocks.len()));
        let len = block.len() as u16;
        zlib.extend(len.to_le_bytes());
        zlib.extend((!len).to_le_bytes());
        zlib.extend_from_slice(block);
    }
    let (mut a, mut b) = (1u32, 0u32);
    for &byte in scanlines {
        a = (a + u32::from(byte)) % 65_521;
        b = (b + a) % 65_521;
    }
    zlib.extend(((b << 16) | a).to_be_bytes());
    let mut out = vec![0x89, b'P', b'N', b'G', 0x0d, 0x0a, 0x1a, 0x0a];
    chunk(&mut out, b"IHDR", &ihdr);
    if let Some(p) = palette {
        chunk(&mut out, b"PLTE", p);
    }
    chunk(&mut out, b"IDAT", &zlib);
    chunk(&mut out, b"IEND", &[]);
    out
}

pub fn ihdr(width: u32, height: u32, depth: u8, color: u8) -> [u8; 13] {
    let mut h = [0u8; 13];
    h[..4].copy_from_slice(&width.to_be_bytes());
    h[4..8].copy_from_slice(&height.to_be_bytes());
    (h[8], h[9]) = (depth, color);
    h
}
