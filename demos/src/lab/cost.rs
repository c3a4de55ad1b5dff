//! Cost: error against force evaluations (work-precision), from the
//! convergence runs.

use tickwork_integrators::math;

/// Force evaluations a method needs to reach `target` error, interpolated
/// log-log between its runs `(evaluations, error)` from the coarsest step
/// down: `Some((n, false))`; `Some((n, true))` when even the coarsest run
/// (`n` evaluations) was already below the target, so `n` is an upper
/// bound; `None` if no run reached it.
#[must_use]
pub fn evaluations_for(runs: impl IntoIterator<Item = (f64, f64)>, target: f64) -> Option<(f64, bool)> {
    let points: Vec<(f64, f64)> = runs.into_iter().filter(|p| p.1.is_finite() && p.1 > 0.0).collect();
    if let Some(first) = points.first()
        && first.1 <= target
    {
        return Some((first.0, true));
    }
    points
        .windows(2)
        .find(|w| w[0].1 > target && w[1].1 <= target)
        .map(|w| {
            let (e0, e1) = (math::ln(w[0].1), math::ln(w[1].1));
            let f = (math::ln(target) - e0) / (e1 - e0);
            (
                math::exp(math::ln(w[0].0) + f * (math::ln(w[1].0) - math::ln(w[0].0))),
                false,
            )
        })
}
