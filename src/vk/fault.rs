//! Fault injection for the tests: environment variables that make the N-th call of a kind fail
//! as the driver would report it, so that every failure path runs on lavapipe, which never
//! fails these calls on its own. `MEADOW_INJECT_ALLOC_FAILURE=N`: the N-th memory allocation of
//! the process runs out of device memory; `MEADOW_INJECT_ACQUIRE_FAILURE=N` and
//! `MEADOW_INJECT_PRESENT_FAILURE=N`: the N-th `vkAcquireNextImageKHR` / `vkQueuePresentKHR` loses
//! the surface; `MEADOW_INJECT_HOST_MEMORY_FAILURE=N`: the N-th `vkCreateShaderModule` (every
//! pipeline makes one) runs out of host memory; `MEADOW_INJECT_FREE_FAILURE=N`: the allocator
//! reports an error for the N-th free (the memory is freed). (Submissions:
//! `MEADOW_INJECT_SUBMIT_FAILURE`, `render::frame::FrameRing`.)
//!
//! The values are checked once, at start (`cli::parse`, before anything logs): a value that is
//! not a call number from 1 (`abc`, `0`, `-1`, 2⁶⁴, an unknown suffix such as `1:SYNC`), or a
//! `MEADOW_INJECT_*` variable meadow does not know, is refused with exit 2, as `MEADOW_HIDE`
//! refuses an unknown entry: a typo must not pass as a switch that injects nothing.
//!
//! Every call of a kind is counted, asked for or not: [`calls`] tells a test where a run is (the
//! viewer's `sample:` lines print the allocations made), so it can aim a failure at one moment.

use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Mutex, OnceLock};

/// A kind of call that can be made to fail.
#[derive(Clone, Copy)]
pub enum Fault {
    /// Memory allocation (`Device::allocate`).
    Allocation,
    /// `vkAcquireNextImageKHR`.
    Acquire,
    /// `vkQueuePresentKHR`.
    Present,
    /// `vkCreateShaderModule`, failing with `VK_ERROR_OUT_OF_HOST_MEMORY`.
    HostMemory,
    /// `Allocator::free`.
    Free,
}

const KINDS: usize = 5;

impl Fault {
    fn variable(self) -> &'static str {
        match self {
            Fault::Allocation => "MEADOW_INJECT_ALLOC_FAILURE",
            Fault::Acquire => "MEADOW_INJECT_ACQUIRE_FAILURE",
            Fault::Present => "MEADOW_INJECT_PRESENT_FAILURE",
            Fault::HostMemory => "MEADOW_INJECT_HOST_MEMORY_FAILURE",
            Fault::Free => "MEADOW_INJECT_FREE_FAILURE",
        }
    }

    fn counter(self) -> &'static AtomicU64 {
        static CALLS: [AtomicU64; KINDS] = [const { AtomicU64::new(0) }; KINDS];
        &CALLS[self as usize]
    }
}

/// Calls of kind `fault` made so far in this process.
pub fn calls(fault: Fault) -> u64 {
    fault.counter().load(Ordering::Relaxed)
}

/// Count one call of kind `fault`; true when it is the one to fail. The variables are read once
/// per process (acquire and present ask every frame).
pub fn fails(fault: Fault) -> bool {
    let call = fault.counter().fetch_add(1, Ordering::Relaxed) + 1;
    record_site(fault);
    switches().nth[fault as usize] == Some(call) || armed(fault).load(Ordering::Relaxed) == call
}

/// The call of each kind [`fail_in`] aimed at (0: none).
fn armed(fault: Fault) -> &'static AtomicU64 {
    static ARMED: [AtomicU64; KINDS] = [const { AtomicU64::new(0) }; KINDS];
    &ARMED[fault as usize]
}

/// Make the `nth` next call of kind `fault` in this process fail (`None`: none), as its
/// variable would: a test that builds many renderers in one process aims at each call in turn.
pub fn fail_in(fault: Fault, nth: Option<u64>) {
    armed(fault).store(nth.map_or(0, |n| calls(fault) + n), Ordering::Relaxed);
}

/// Where the calls of each kind were made while recording (`record_sites`), in call order.
fn sites_of(fault: Fault) -> &'static Mutex<Option<Vec<String>>> {
    static SITES: [Mutex<Option<Vec<String>>>; KINDS] = [const { Mutex::new(None) }; KINDS];
    &SITES[fault as usize]
}

/// Record the call site of every call of kind `fault` from now on, until [`sites`] takes them:
/// a test runs a construction once, then aims one failure at each distinct site.
pub fn record_sites(fault: Fault) {
    *sites_of(fault).lock().unwrap_or_else(|p| p.into_inner()) = Some(Vec::new());
}

/// The call sites recorded since [`record_sites`], one per call in call order, and stop
/// recording. A site is the call's stack through meadow's own source files (`src/…:line`).
pub fn sites(fault: Fault) -> Vec<String> {
    sites_of(fault).lock().unwrap_or_else(|p| p.into_inner()).take().unwrap_or_default()
}

fn record_site(fault: Fault) {
    let mut sites = sites_of(fault).lock().unwrap_or_else(|p| p.into_inner());
    if let Some(sites) = sites.as_mut() {
        let trace = std::backtrace::Backtrace::force_capture().to_string();
        let frames: Vec<&str> = trace
            .lines()
            .filter_map(|line| line.trim().strip_prefix("at "))
            .filter(|at| at.contains("src/") && !at.contains("/rustc/") && !at.contains("/.cargo/"))
            .collect();
        sites.push(frames.join(" < "));
    }
}

/// `MEADOW_INJECT_SUBMIT_FAILURE`: the submission to fail (`render::frame::FrameRing`).
pub fn submit_failure() -> Option<u64> {
    switches().submit
}

/// `MEADOW_INJECT_WRITE_FAILURE`: the file write to fail, and whether at its `sync_all` (the
/// `:sync` suffix) rather than half-way (`app::output`).
pub fn write_failure() -> Option<(u64, bool)> {
    switches().write
}

/// The switches' parsed values.
#[derive(Debug, Default, PartialEq, Eq)]
struct Switches {
    nth: [Option<u64>; KINDS],
    submit: Option<u64>,
    write: Option<(u64, bool)>,
}

const SUBMIT: &str = "MEADOW_INJECT_SUBMIT_FAILURE";
const WRITE: &str = "MEADOW_INJECT_WRITE_FAILURE";
const ALL: [Fault; KINDS] = [Fault::Allocation, Fault::Acquire, Fault::Present, Fault::HostMemory, Fault::Free];

/// Check every `MEADOW_INJECT_*` variable of the environment (once per process; the binary calls
/// this at start, before anything logs): an unknown one, or a bad value, is bad input.
pub fn check_environment() -> crate::Result<()> {
    parsed().as_ref().map(|_| ()).map_err(|e| crate::Error::bad_input(e.clone()))
}

/// The parsed switches; none when the environment is invalid (a library caller that did not call
/// [`check_environment`] then injects nothing).
fn switches() -> &'static Switches {
    static NONE: Switches = Switches { nth: [None; KINDS], submit: None, write: None };
    parsed().as_ref().unwrap_or(&NONE)
}

fn parsed() -> &'static Result<Switches, String> {
    static PARSED: OnceLock<Result<Switches, String>> = OnceLock::new();
    PARSED.get_or_init(|| {
        let vars = std::env::vars_os().filter(|(name, _)| name.to_string_lossy().starts_with("MEADOW_INJECT_"));
        parse(vars.map(|(name, value)| (name.to_string_lossy().into_owned(), value)))
    })
}

/// Parse the `MEADOW_INJECT_*` variables `vars` (name, value).
fn parse(vars: impl Iterator<Item = (String, std::ffi::OsString)>) -> Result<Switches, String> {
    let mut switches = Switches::default();
    let mut vars: Vec<_> = vars.collect();
    vars.sort();
    for (name, value) in vars {
        let text = value.to_str().ok_or_else(|| format!("{name}: the value is not UTF-8"))?;
        let quoted = quote(text);
        let bad = |what: &str| format!("{name}={quoted}: {what}");
        let nth = |digits: &str| -> Result<u64, String> {
            match digits.trim().parse::<u64>() {
                Ok(0) => Err(bad("calls are counted from 1: give N >= 1 (the N-th call fails)")),
                Ok(n) => Ok(n),
                Err(_) if !digits.trim().is_empty() && digits.trim().bytes().all(|b| b.is_ascii_digit()) => {
                    Err(bad(&format!("over {} calls, which no run makes", u64::MAX)))
                }
                Err(_) => Err(bad("not a call number: give N >= 1 (the N-th call fails)")),
            }
        };
        if let Some(fault) = ALL.iter().find(|f| f.variable() == name) {
            switches.nth[*fault as usize] = Some(nth(text)?);
        } else if name == SUBMIT {
            switches.submit = Some(nth(text)?);
        } else if name == WRITE {
            let (digits, sync) = match text.split_once(':') {
                None => (text, false),
                Some((digits, "sync")) => (digits, true),
                Some((_, suffix)) => {
                    return Err(bad(&format!("unknown suffix {}: give N or N:sync", quote(&format!(":{suffix}")))))
                }
            };
            switches.write = Some((nth(digits)?, sync));
        } else {
            let mut known: Vec<&str> = ALL.iter().map(|f| f.variable()).collect();
            known.extend([SUBMIT, WRITE]);
            let name = crate::error::quoted(&name);
            return Err(format!("{name}={quoted}: unknown switch (meadow knows {})", known.join(", ")));
        }
    }
    Ok(switches)
}

/// `text` in quotes, as every error quotes user text (`error::quoted`: at most about 80
/// characters).
fn quote(text: &str) -> String {
    format!("'{}'", crate::error::quoted(text))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn one(name: &str, value: &str) -> Result<Switches, String> {
        parse(std::iter::once((name.to_string(), value.into())))
    }

    #[test]
    fn good_values_parse_and_bad_ones_are_refused() {
        assert_eq!(one("MEADOW_INJECT_ALLOC_FAILURE", "3").map(|s| s.nth[0]), Ok(Some(3)));
        assert_eq!(one("MEADOW_INJECT_FREE_FAILURE", " 1 ").map(|s| s.nth[4]), Ok(Some(1)));
        assert_eq!(one(WRITE, "2:sync").map(|s| s.write), Ok(Some((2, true))));
        assert_eq!(one(WRITE, "2").map(|s| s.write), Ok(Some((2, false))));
        assert_eq!(one(SUBMIT, "5").map(|s| s.submit), Ok(Some(5)));
        for name in ALL.iter().map(|f| f.variable()).chain([SUBMIT, WRITE]) {
            for bad in ["abc", "0", "-1", "18446744073709551616", "1:SYNC", "", "1.5"] {
                let e = one(name, bad).expect_err(bad);
                assert!(e.starts_with(&format!("{name}='{bad}': ")), "{e}");
            }
        }
        assert!(one("MEADOW_INJECT_ALOC_FAILURE", "1").expect_err("typo").contains("unknown switch"));
        let long = one("MEADOW_INJECT_ALLOC_FAILURE", &"x".repeat(10_000)).expect_err("long");
        assert!(long.len() < 200, "{long}");
    }
}
