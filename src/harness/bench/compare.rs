//! `meadow bench --compare OLD NEW`: two bench.json documents, each validated against
//! `docs/bench.schema.json` (the `jsonschema` crate), refused when they do not describe
//! comparable runs (device, driver, resolution, build profile, rasteriser threads), and compared
//! per (row, variant): the change of the median GPU time, flagged when it is beyond the noise
//! threshold *and* significant on the per-frame samples (a one-sided Mann–Whitney U test at
//! 5 %), so a noisy frame cannot fail a CI gate on its own.

use std::path::Path;

use serde_json::Value;

use super::document::{BenchDocument, BenchRow, VariantMeasured};
use crate::error::{quoted, Error, Result};

/// The schema every bench.json follows (`docs/bench.schema.json`).
const SCHEMA: &str = include_str!("../../../docs/bench.schema.json");

/// Significance level of the one-sided test.
const ALPHA: f64 = 0.05;

/// Fewest frames per side for the test to mean anything (with 4 and 4, the smallest one-sided
/// p-value is 1/70).
const MIN_FRAMES: usize = 4;

/// Largest bench.json `--compare` reads: a thesis run with every frame's sample is well under a
/// megabyte.
const MOST_BYTES: u64 = 64 << 20;

/// Memory a parsed document takes per byte of its text, at most: a `serde_json::Value` of 32
/// bytes per two-byte number (`0,`), twice that while its array grows.
const PARSED_PER_BYTE: u64 = 32;

/// Fields that must be equal for two runs to be comparable: each as the document writes it.
fn same_run(doc: &BenchDocument) -> [(&'static str, String); 5] {
    let h = &doc.header;
    [
        ("device", json(&h.device)),
        ("driver", json(&h.driver)),
        ("resolution", json(&h.resolution)),
        ("build_profile", json(&h.build_profile)),
        ("lp_num_threads", json(&h.lp_num_threads)),
    ]
}

/// A field's JSON text (`"llvmpipe"`, `[640,360]`, `null`).
fn json(field: &impl serde::Serialize) -> String {
    serde_json::to_string(field).expect("a document field serialises")
}

/// Read a bench.json: validated against the schema, then read as a [`BenchDocument`] (bad
/// input, exit 2, naming the field, when it does not follow either: a measured variant without
/// its `frames` is refused, not read as none).
pub fn load(path: &Path) -> Result<BenchDocument> {
    let text = crate::app::input::read_text(path, "--compare", MOST_BYTES, PARSED_PER_BYTE)?;
    let shown = quoted(&path.display().to_string()).into_owned();
    let doc: Value =
        serde_json::from_str(&text).map_err(|e| Error::bad_input(format!("{shown}: not a bench.json: {e}")))?;
    let schema: Value = serde_json::from_str(SCHEMA).expect("docs/bench.schema.json is JSON");
    let validator = jsonschema::validator_for(&schema).expect("docs/bench.schema.json is a valid schema");
    if let Some(e) = validator.iter_errors(&doc).next() {
        let at = e.instance_path().to_string();
        let at = if at.is_empty() { "the document".to_string() } else { at };
        // The schema's message quotes the offending value: bounded like every quote of input.
        let (at, e) = (quoted(&at), quoted(&e.to_string()).into_owned());
        return Err(Error::bad_input(format!("{shown}: not a bench.json: {at}: {e}")));
    }
    // The message names the field (`missing field \`frames\``): bounded like every quote of input.
    serde_json::from_value(doc)
        .map_err(|e| Error::bad_input(format!("{shown}: not a bench.json: {}", quoted(&e.to_string()))))
}

/// Compare two runs: per (row, variant) change of the median GPU time in %. Returns the report
/// and whether any change is a significant regression beyond `threshold_pct`; refuses a
/// non-positive threshold, runs that are not comparable, medians that are not positive and
/// changes that are not finite.
pub fn compare(old: &BenchDocument, new: &BenchDocument, threshold_pct: f64) -> Result<(String, bool)> {
    if !(threshold_pct.is_finite() && threshold_pct > 0.0) {
        return Err(Error::bad_input(format!("--threshold {threshold_pct}: must be a positive percentage")));
    }
    let differences: Vec<String> = same_run(old)
        .into_iter()
        .zip(same_run(new))
        .filter(|((_, a), (_, b))| a != b)
        .map(|((k, a), (_, b))| format!("{k} {} vs {}", quoted(&a), quoted(&b)))
        .collect();
    if !differences.is_empty() {
        return Err(Error::bad_input(format!("the runs are not comparable: {}", differences.join(", "))));
    }
    if copy_apart(old) != copy_apart(new) {
        return Err(Error::bad_input(
            "the runs are not comparable: one run's gpu_ms includes the read-back copy (no readback_ms: recorded \
             before meadow reported the copy apart)",
        ));
    }
    let mut out = format!(
        "{:>9} {:>4} {:<16} {:>10} {:>10} {:>8} {:>7}\n",
        "blades", "seg", "variant", "old ms", "new ms", "change", "p"
    );
    let (mut regressed, mut compared) = (false, 0);
    for row in &new.rows {
        let same = old.rows.iter().find(|r| r.blades == row.blades && r.segments == row.segments);
        let Some(old_row) = same else { continue };
        for v in &row.variants {
            // Unsupported on either side: not compared.
            let (Some(old_v), Some(new_v)) = (old_row.variant(&v.variant), v.outcome.measured()) else { continue };
            let (line, flagged) = judge(row, &v.variant, old_v, new_v, threshold_pct)?;
            out.push_str(&line);
            regressed |= flagged;
            compared += 1;
        }
    }
    if compared == 0 {
        // An empty report would pass a CI gate.
        return Err(Error::bad_input("the runs have no blade count, segment count and variant measured in both"));
    }
    out.push_str(&format!(
        "noise threshold: {threshold_pct:.1} %; flagged when beyond it and significant (one-sided Mann-Whitney, p < {ALPHA})\n"
    ));
    Ok((out, regressed))
}

/// Whether `doc`'s GPU times leave out the read-back copy (its variants carry `readback_ms`).
fn copy_apart(doc: &BenchDocument) -> bool {
    let mut variants = doc.rows.iter().flat_map(|r| &r.variants);
    variants.any(|v| v.outcome.measured().is_some_and(|m| m.readback_ms.is_some()))
}

/// The report line of variant `name` of `row`, measured as `old_v` then `v`, and whether it is a
/// regression. Refuses medians that are not positive and a change that is not finite (a median
/// near `f64::MAX` overflows `100 (new - old) / old`, which would read as an infinite speed-up
/// or regression).
fn judge(
    row: &BenchRow,
    name: &str,
    old_v: &VariantMeasured,
    v: &VariantMeasured,
    threshold_pct: f64,
) -> Result<(String, bool)> {
    let (a, b) = (old_v.gpu_ms.median, v.gpu_ms.median);
    let at = format!("{} blades x {} segments, {}", row.blades, row.segments, quoted(name));
    if !(a.is_finite() && a > 0.0 && b.is_finite() && b > 0.0) {
        return Err(Error::bad_input(format!("{at}: medians {} and {} ms are not both positive", ms(a), ms(b))));
    }
    let change = 100.0 * (b - a) / a;
    if !change.is_finite() {
        return Err(Error::bad_input(format!(
            "{at}: medians {} and {} ms give a change that is not finite",
            ms(a),
            ms(b)
        )));
    }
    // Every sample is finite: serde_json refuses a number out of f64's range when parsing, and
    // JSON cannot hold NaN or an infinity.
    let (before, after) = (samples(old_v), samples(v));
    let judged = before.len() >= MIN_FRAMES && after.len() >= MIN_FRAMES;
    let (slower, faster) = (b > a, b < a);
    let p = judged.then(|| match slower {
        true => mann_whitney_greater(&before, &after),
        false => mann_whitney_greater(&after, &before),
    });
    let beyond = change.abs() > threshold_pct;
    let significant = p.is_some_and(|p| p < ALPHA);
    let flag = match (beyond, significant, judged) {
        (true, true, _) if slower => "  REGRESSION",
        (true, true, _) if faster => "  faster",
        (true, false, true) => "  within noise (not significant)",
        (true, false, false) => "  not judged (fewer than 4 frames a side)",
        _ => "",
    };
    let p = p.map_or("-".to_string(), |p| format!("{p:.3}"));
    let line = format!(
        "{:>9} {:>4} {:<16} {:>10.3} {:>10.3} {:>7.1}% {:>7}{flag}\n",
        row.blades, row.segments, name, a, b, change, p
    );
    Ok((line, beyond && significant && slower))
}

/// A time in ms for a message: as written between 1e-6 and 1e9 (and 0), in scientific notation
/// outside (Rust writes `1e308` out in 309 digits).
fn ms(x: f64) -> String {
    match x == 0.0 || (1e-6..1e9).contains(&x.abs()) {
        true => format!("{x}"),
        false => format!("{x:e}"),
    }
}

/// The per-frame GPU times of a variant.
fn samples(v: &VariantMeasured) -> Vec<f64> {
    v.frames.iter().map(|f| f.gpu_ms).collect()
}

/// One-sided p-value that `after` tends to be larger than `before` (Mann–Whitney U, normal
/// approximation with the tie correction and a continuity correction).
fn mann_whitney_greater(before: &[f64], after: &[f64]) -> f64 {
    let (n1, n2) = (before.len() as f64, after.len() as f64);
    let mut all: Vec<(f64, bool)> =
        before.iter().map(|&x| (x, false)).chain(after.iter().map(|&x| (x, true))).collect();
    all.sort_by(|a, b| a.0.total_cmp(&b.0));
    // Mid-ranks of ties, and the tie correction's sum of t³ - t.
    let (mut rank_after, mut ties) = (0.0, 0.0);
    let mut i = 0;
    while i < all.len() {
        let j = (i..all.len()).find(|&j| all[j].0 != all[i].0).unwrap_or(all.len());
        let rank = (i + 1 + j) as f64 / 2.0;
        rank_after += rank * all[i..j].iter().filter(|(_, late)| *late).count() as f64;
        let t = (j - i) as f64;
        ties += t * t * t - t;
        i = j;
    }
    let u = rank_after - n2 * (n2 + 1.0) / 2.0;
    let n = n1 + n2;
    let variance = n1 * n2 / 12.0 * ((n + 1.0) - ties / (n * (n - 1.0)));
    if variance <= 0.0 {
        return 1.0;
    }
    let z = (u - n1 * n2 / 2.0 - 0.5) / variance.sqrt();
    0.5 * erfc(z / std::f64::consts::SQRT_2)
}

/// The complementary error function (Numerical Recipes' `erfcc`, relative error below 1.2e-7).
fn erfc(x: f64) -> f64 {
    let z = x.abs();
    let t = 1.0 / (1.0 + 0.5 * z);
    let poly = -z * z - 1.265_512_23
        + t * (1.000_023_68
            + t * (0.374_091_96
                + t * (0.096_784_18
                    + t * (-0.186_288_06
                        + t * (0.278_868_07
                            + t * (-1.135_203_98 + t * (1.488_515_87 + t * (-0.822_152_23 + t * 0.170_872_77))))))));
    let r = t * poly.exp();
    if x >= 0.0 {
        r
    } else {
        2.0 - r
    }
}

#[cfg(test)]
mod tests {
    use super::super::document::fixtures;
    use super::*;

    /// A run of one row whose static variant's frames took `frames` ms, its median the
    /// upper middle one.
    fn doc(frames: &[f64]) -> BenchDocument {
        let mut doc = fixtures::doc(vec![fixtures::row(1000, &[("static", frames)])]);
        let mut sorted = frames.to_vec();
        sorted.sort_by(f64::total_cmp);
        if let crate::harness::document::Outcome::Measured(m) = &mut doc.rows[0].variants[0].outcome {
            m.gpu_ms.median = sorted[sorted.len() / 2];
        }
        doc
    }

    #[test]
    fn a_regression_must_be_beyond_the_threshold_and_significant() {
        let base = doc(&[10.0, 10.2, 9.9, 10.1, 10.0, 9.8, 10.3, 10.1]);
        let slower = doc(&[13.0, 13.2, 12.9, 13.1, 13.0, 12.8, 13.3, 13.1]);
        let (report, regressed) = compare(&base, &slower, 10.0).expect("comparable");
        assert!(regressed && report.contains("REGRESSION"), "{report}");
        let (report, regressed) = compare(&slower, &base, 10.0).expect("comparable");
        assert!(!regressed && report.contains("faster"), "{report}");
        // The same median shift, but one slow frame among otherwise equal ones: not significant.
        let noisy = doc(&[10.0, 10.2, 9.9, 10.1, 13.0, 9.8, 10.3, 13.5]);
        let noisier = doc(&[13.0, 9.9, 10.1, 13.1, 10.0, 13.4, 10.2, 13.0]);
        let (report, regressed) = compare(&noisy, &noisier, 1.0).expect("comparable");
        assert!(!regressed && report.contains("not significant"), "{report}");
        assert!(!compare(&base, &base, 10.0).expect("comparable").1);
    }

    #[test]
    fn bad_thresholds_medians_and_other_machines_are_refused() {
        let base = doc(&[10.0, 10.2, 9.9, 10.1]);
        for threshold in [0.0, -5.0, f64::NAN, f64::INFINITY] {
            assert!(compare(&base, &base, threshold).is_err(), "threshold {threshold}");
        }
        let zero = doc(&[0.0, 0.0, 0.0, 0.0]);
        assert!(compare(&base, &zero, 10.0).is_err() && compare(&zero, &base, 10.0).is_err());
        // 100 (new - old) / old overflows: refused both ways, the medians written short.
        let huge = doc(&[1e308, 1e308, 1e308, 1e308]);
        for (a, b) in [(&huge, &base), (&base, &huge)] {
            let e = compare(a, b, 10.0).expect_err("not finite").to_string();
            assert!(e.contains("static") && e.contains("1e308") && e.contains("not finite"), "{e}");
        }
        let mut other = base.clone();
        other.header.device = "another GPU".into();
        let e = compare(&base, &other, 10.0).expect_err("not comparable").to_string();
        assert!(e.contains("not comparable") && e.contains("device"), "{e}");
    }

    #[test]
    fn the_test_statistic_matches_known_values() {
        // Completely separated samples of 4 and 4: the exact one-sided p is 1/70 = 0.014; the
        // normal approximation with continuity correction gives 0.0152.
        let p = mann_whitney_greater(&[1.0, 2.0, 3.0, 4.0], &[5.0, 6.0, 7.0, 8.0]);
        assert!((p - 0.0152).abs() < 0.001, "{p}");
        // Identical samples: no evidence either way.
        assert!(mann_whitney_greater(&[1.0; 5], &[1.0; 5]) >= 0.5);
        assert!((erfc(0.0) - 1.0).abs() < 1e-7 && (erfc(1.0) - 0.157_299_2).abs() < 1e-6);
    }
}
