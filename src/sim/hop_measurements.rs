//! What the hop-resolution measurements say about a step that under-resolves the wheel hop: the error
//! that `AccuracyPolicy::Warn` logs. The measurements are the generated reports themselves
//! (docs/hop_resolution_*.md, written by `examples/hop_resolution.rs`), compiled in and read here, so that
//! the warning quotes the one source of those figures and cannot drift from it.

use crate::integrate::IntegratorKind;

/// The reports of one scheme: the suite's road cases and its stiff bump variants.
fn reports(kind: IntegratorKind) -> &'static [&'static str] {
    match kind {
        IntegratorKind::Rk4 => {
            &[include_str!("../../docs/hop_resolution_rk4.md"), include_str!("../../docs/hop_resolution_stiff_rk4.md")]
        }
        IntegratorKind::ImexAb3 => &[
            include_str!("../../docs/hop_resolution_imex.md"),
            include_str!("../../docs/hop_resolution_stiff_imex.md"),
        ],
        IntegratorKind::Ab3 | IntegratorKind::Dopri5 => &[],
    }
}

/// One measured run: its vehicle and case, step (ms), |hλ| of the fastest hop mode and error over the
/// suite's tolerance (a run the scheme's own monitor stopped: up to its stop).
#[derive(Debug, Clone, PartialEq)]
pub struct Measured {
    pub vehicle: String,
    pub case: String,
    pub step_ms: f64,
    pub h_lambda: f64,
    pub error_per_tolerance: f64,
}

/// The table rows of a report (`| vehicle | case | h (ms) | |hλ| hop | outcome | error / tolerance |`).
pub fn parse(report: &str) -> Vec<Measured> {
    report
        .lines()
        .filter_map(|line| {
            let cells: Vec<&str> = line.trim().trim_matches('|').split(" | ").map(str::trim).collect();
            let [vehicle, case, step, h_lambda, _outcome, error] = cells[..] else { return None };
            Some(Measured {
                vehicle: vehicle.to_string(),
                case: case.to_string(),
                step_ms: step.parse().ok()?,
                h_lambda: h_lambda.parse().ok()?,
                error_per_tolerance: error.parse().ok()?,
            })
        })
        .collect()
}

/// A sentence on the error to expect at `h_lambda` (|hλ| of the fastest wheel-hop mode) with `kind`: the
/// largest error of the measured runs whose |hλ| is at most this one, and where the measurements end.
pub fn expected_error(kind: IntegratorKind, h_lambda: f64) -> String {
    let runs: Vec<Measured> = reports(kind).iter().flat_map(|r| parse(r)).collect();
    if runs.is_empty() {
        return format!(
            "|hλ| = {h_lambda:.2}; no hop-resolution measurements exist for {kind:?}: the error is unknown"
        );
    }
    let largest = runs.iter().map(|m| m.h_lambda).fold(0.0, f64::max);
    let worst = runs
        .iter()
        .filter(|m| m.h_lambda <= h_lambda)
        .max_by(|a, b| a.error_per_tolerance.total_cmp(&b.error_per_tolerance));
    let beyond = if h_lambda > largest {
        format!("; beyond the measured range (|hλ| up to {largest:.2}) the error may be larger")
    } else {
        String::new()
    };
    match worst {
        Some(m) => format!(
            "The hop-resolution measurements (docs/hop_resolution_*.md, {kind:?}) found runs at |hλ| ≤ {h_lambda:.2} off \
             by up to {:.1}x the stability suite's tolerance (the worst: {}, {}, {} ms, |hλ| = {:.2}){beyond}",
            m.error_per_tolerance, m.vehicle, m.case, m.step_ms, m.h_lambda
        ),
        None => format!(
            "|hλ| = {h_lambda:.2} is below every measured run's (docs/hop_resolution_*.md, {kind:?}): within the \
             tolerance there"
        ),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_report_has_its_rows() {
        // Six steps per case: three road cases on three vehicles, and the stiff variants' reports.
        for kind in [IntegratorKind::Rk4, IntegratorKind::ImexAb3] {
            for report in reports(kind) {
                let rows = parse(report);
                assert!(rows.len() >= 24 && rows.len() % 6 == 0, "{kind:?}: {} rows", rows.len());
                assert!(rows.iter().all(|m| m.h_lambda > 0.0 && m.error_per_tolerance >= 0.0));
            }
        }
    }

    #[test]
    fn the_expected_error_is_the_worst_measured_at_or_below() {
        // RK4's report has the HMMWV's 20 cm bump at 8.33 ms (|hλ| 0.614, 18.1x) and the MacPherson import's
        // at 2.08 ms (|hλ| 0.630, 0.843x): at 0.62 the worst is the HMMWV's.
        let runs: Vec<Measured> = reports(IntegratorKind::Rk4).iter().flat_map(|r| parse(r)).collect();
        let expect = runs.iter().filter(|m| m.h_lambda <= 0.62).map(|m| m.error_per_tolerance).fold(0.0, f64::max);
        let said = expected_error(IntegratorKind::Rk4, 0.62);
        assert!(said.contains(&format!("{expect:.1}x")), "{said}");
        assert!(expected_error(IntegratorKind::Ab3, 0.5).contains("unknown"));
        assert!(expected_error(IntegratorKind::Rk4, 1e-6).contains("below every measured run"));
        assert!(expected_error(IntegratorKind::Rk4, 100.0).contains("beyond the measured range"));
    }
}
