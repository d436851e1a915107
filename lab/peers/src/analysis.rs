//! From runs to figures at equal error: interpolation on a method's ladder,
//! each suite's best, the physical limit, the ratios.

use crate::methods::Suite;

/// One measured run of one method at one setting on one problem.
#[derive(Clone, Debug)]
pub struct Row {
    /// The problem.
    pub problem: &'static str,
    /// Who wrote the method.
    pub suite: Suite,
    /// The method.
    pub method: &'static str,
    /// Relative tolerance or step size.
    pub setting: f64,
    /// Accepted steps.
    pub steps: usize,
    /// Right-hand-side calls.
    pub rhs: usize,
    /// Jacobian calls (a method's finite differences are right-hand sides).
    pub jacobian: usize,
    /// Median CPU time of the measuring thread, seconds.
    pub seconds: f64,
    /// Median wall time, seconds.
    pub wall_seconds: f64,
    /// Error at the final time: max abs over the state against the reference.
    pub error: f64,
    /// (seconds − rhs × rhs cost − jacobian × Jacobian cost) / steps: the
    /// method's own work per step.
    pub overhead_per_step: f64,
}

/// A value read off a method's ladder at a target error.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AtError {
    /// The value.
    pub value: f64,
    /// `false`: interpolated between two runs whose errors bracket the
    /// target; `true`: no run had an error above the target, and this is
    /// the least value among runs below it (an upper bound).
    pub bound: bool,
}

/// The value `y` of a ladder of runs `(error, y)` (in ladder order) at
/// `target` error: log y interpolated linearly in log error between two
/// neighbouring runs whose errors bracket the target, the least such value
/// when several pairs bracket it (the method's best); without a bracketing
/// pair, the least `y` among runs with error ≤ target, as a bound; `None`
/// when no run reached the target.
///
/// ```
/// use nh_peers::analysis::at_error;
/// // error 1e-4 in 1 s, 1e-8 in 100 s: 1e-6 is half-way (in logs), at 10 s
/// let t = at_error(&[(1e-4, 1.0), (1e-8, 100.0)], 1e-6).unwrap();
/// assert!((t.value - 10.0).abs() < 1e-9 && !t.bound);
/// ```
pub fn at_error(points: &[(f64, f64)], target: f64) -> Option<AtError> {
    let ok = |&(e, y): &(f64, f64)| e > 0.0 && e.is_finite() && y > 0.0 && y.is_finite();
    let mut best: Option<f64> = None;
    for w in points.windows(2) {
        let (a, b) = (w[0], w[1]);
        if !(ok(&a) && ok(&b)) || (a.0 - target) * (b.0 - target) > 0.0 {
            continue;
        }
        let y = if a.0 == b.0 {
            a.1.min(b.1)
        } else {
            let s = (target.ln() - a.0.ln()) / (b.0.ln() - a.0.ln());
            (a.1.ln() + s * (b.1.ln() - a.1.ln())).exp()
        };
        best = Some(best.map_or(y, |v: f64| v.min(y)));
    }
    if let Some(value) = best {
        return Some(AtError {
            value,
            bound: false,
        });
    }
    points
        .iter()
        .filter(|p| ok(p) && p.0 <= target)
        .map(|p| p.1)
        .min_by(f64::total_cmp)
        .map(|value| AtError { value, bound: true })
}

/// The rows of one method on one problem, in ladder order.
pub fn ladder<'a>(rows: &'a [Row], problem: &str, method: &str) -> Vec<&'a Row> {
    rows.iter()
        .filter(|r| r.problem == problem && r.method == method)
        .collect()
}

/// A method's wall time at `target` error.
pub fn seconds_at(rows: &[Row], problem: &str, method: &str, target: f64) -> Option<AtError> {
    let pts: Vec<(f64, f64)> = ladder(rows, problem, method)
        .iter()
        .map(|r| (r.error, r.seconds))
        .collect();
    at_error(&pts, target)
}

/// A method's right-hand-side calls at `target` error.
pub fn rhs_at(rows: &[Row], problem: &str, method: &str, target: f64) -> Option<AtError> {
    let pts: Vec<(f64, f64)> = ladder(rows, problem, method)
        .iter()
        .map(|r| (r.error, r.rhs as f64))
        .collect();
    at_error(&pts, target)
}

/// A method's own work per step at `target` error.
pub fn overhead_at(rows: &[Row], problem: &str, method: &str, target: f64) -> Option<AtError> {
    let pts: Vec<(f64, f64)> = ladder(rows, problem, method)
        .iter()
        .map(|r| (r.error, r.overhead_per_step))
        .collect();
    at_error(&pts, target)
}

/// The methods of `rows` on `problem`, in order of first appearance.
pub fn methods(rows: &[Row], problem: &str) -> Vec<(Suite, &'static str)> {
    let mut out: Vec<(Suite, &'static str)> = Vec::new();
    for r in rows.iter().filter(|r| r.problem == problem) {
        if !out.iter().any(|m| m.1 == r.method) {
            out.push((r.suite, r.method));
        }
    }
    out
}

/// A suite's best method at `target` error: (method, time).
pub fn suite_best(
    rows: &[Row],
    problem: &str,
    suite: Suite,
    target: f64,
) -> Option<(&'static str, AtError)> {
    methods(rows, problem)
        .into_iter()
        .filter(|m| m.0 == suite)
        .filter_map(|m| seconds_at(rows, problem, m.1, target).map(|t| (m.1, t)))
        .min_by(|a, b| a.1.value.total_cmp(&b.1.value))
}

/// The fewest right-hand-side calls any method needed for `target` error:
/// (method, calls).
pub fn fewest_rhs(rows: &[Row], problem: &str, target: f64) -> Option<(&'static str, AtError)> {
    methods(rows, problem)
        .into_iter()
        .filter_map(|m| rhs_at(rows, problem, m.1, target).map(|c| (m.1, c)))
        .min_by(|a, b| a.1.value.total_cmp(&b.1.value))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn interpolates_log_linearly_between_bracketing_runs() {
        // error 1e-4 at 1 s, 1e-8 at 100 s: 1e-6 lies half-way in log, at 10 s
        let v = at_error(&[(1e-4, 1.0), (1e-8, 100.0)], 1e-6).unwrap();
        assert!(!v.bound);
        assert!((v.value - 10.0).abs() < 1e-9, "{v:?}");
    }

    #[test]
    fn takes_the_best_of_several_brackets() {
        // the error is not monotone: two pairs bracket 1e-6
        let pts = [(1e-5, 1.0), (1e-7, 3.0), (1e-5, 5.0), (1e-7, 9.0)];
        let v = at_error(&pts, 1e-6).unwrap();
        assert!((v.value - 3f64.sqrt()).abs() < 1e-12, "{v:?}");
    }

    #[test]
    fn bounds_and_misses() {
        // every run already below the target: the cheapest is a bound
        let v = at_error(&[(1e-9, 2.0), (1e-10, 3.0)], 1e-6).unwrap();
        assert_eq!(
            v,
            AtError {
                value: 2.0,
                bound: true
            }
        );
        // no run reaches the target
        assert_eq!(at_error(&[(1e-3, 2.0), (1e-5, 3.0)], 1e-6), None);
        // failed runs (non-finite error) are skipped
        assert_eq!(
            at_error(&[(f64::NAN, 1.0), (1e-7, 2.0)], 1e-6)
                .unwrap()
                .value,
            2.0
        );
    }
}
