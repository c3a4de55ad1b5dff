//! Every method by name: the table `tickwork integrators` prints, and the
//! constructor behind `--integrator NAME`.

use core::fmt;

use crate::integrator::{Integrator, MethodInfo};
use crate::methods::*;
use crate::vector::Vector;

/// Every method, in the order of the lecture (first-order, second-order,
/// higher-order), then the methods beyond it.
pub const METHODS: &[MethodInfo] = &[
    explicit_euler::INFO,
    semi_implicit_euler::INFO,
    implicit_euler::INFO,
    predictor_corrector_euler::INFO,
    exponential_euler::INFO,
    midpoint::INFO,
    heun::INFO,
    trapezoidal::INFO,
    leapfrog::INFO,
    position_verlet::INFO,
    velocity_verlet::INFO,
    beeman::INFO,
    newmark_beta::INFO,
    rk4::INFO,
    adams_bashforth2::INFO,
    adams_bashforth3::INFO,
    adams_bashforth4::INFO,
    forest_ruth::INFO,
    dormand_prince::INFO,
];

/// A name that matches no method.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct UnknownMethod {
    /// The name as given.
    pub name: String,
    /// The canonical names that would have been accepted.
    pub valid: Vec<&'static str>,
}

impl UnknownMethod {
    /// An unknown name among the linear methods of [`METHODS`].
    #[must_use]
    pub fn new(name: &str) -> Self {
        Self {
            name: name.to_owned(),
            valid: METHODS.iter().map(|m| m.name).collect(),
        }
    }
}

impl fmt::Display for UnknownMethod {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "unknown integrator '{}'; valid names are: {}",
            self.name,
            self.valid.join(", ")
        )?;
        write!(f, " (aliases are listed by `tickwork integrators`)")
    }
}

impl std::error::Error for UnknownMethod {}

/// Names compare case-insensitively, with `-`, `_` and spaces equivalent.
fn same_name(given: &str, known: &str) -> bool {
    let mut a = given
        .trim()
        .chars()
        .filter(|c| !matches!(c, '-' | '_' | ' '))
        .map(|c| c.to_ascii_lowercase());
    let mut b = known.chars().filter(|c| *c != '_');
    loop {
        match (a.next(), b.next()) {
            (None, None) => return true,
            (Some(x), Some(y)) if x == y => {}
            _ => return false,
        }
    }
}

/// Looks a method up by name or alias.
///
/// # Errors
/// [`UnknownMethod`], whose message lists the valid names.
pub fn find(name: &str) -> Result<&'static MethodInfo, UnknownMethod> {
    METHODS
        .iter()
        .find(|m| same_name(name, m.name) || m.aliases.iter().any(|alias| same_name(name, alias)))
        .ok_or_else(|| UnknownMethod::new(name))
}

/// Builds a method by name or alias, with its default settings.
///
/// # Errors
/// [`UnknownMethod`], whose message lists the valid names.
pub fn build<V: Vector>(name: &str) -> Result<Box<dyn Integrator<V>>, UnknownMethod> {
    let info = find(name)?;
    Ok(match info.name {
        "explicit_euler" => Box::new(explicit_euler::ExplicitEuler::new()),
        "semi_implicit_euler" => Box::new(semi_implicit_euler::SemiImplicitEuler::new()),
        "implicit_euler" => Box::new(implicit_euler::ImplicitEuler::new()),
        "predictor_corrector_euler" => Box::new(predictor_corrector_euler::PredictorCorrectorEuler::new()),
        "exponential_euler" => Box::new(exponential_euler::ExponentialEuler::new()),
        "midpoint" => Box::new(midpoint::Midpoint::new()),
        "heun" => Box::new(heun::Heun::new()),
        "trapezoidal" => Box::new(trapezoidal::Trapezoidal::new()),
        "leapfrog" => Box::new(leapfrog::Leapfrog::new()),
        "position_verlet" => Box::new(position_verlet::PositionVerlet::new()),
        "velocity_verlet" => Box::new(velocity_verlet::VelocityVerlet::new()),
        "beeman" => Box::new(beeman::Beeman::new()),
        "newmark_beta" => Box::new(newmark_beta::NewmarkBeta::new()),
        "rk4" => Box::new(rk4::Rk4::new()),
        "adams_bashforth2" => Box::new(adams_bashforth2::AdamsBashforth2::new()),
        "adams_bashforth3" => Box::new(adams_bashforth3::AdamsBashforth3::new()),
        "adams_bashforth4" => Box::new(adams_bashforth4::AdamsBashforth4::new()),
        "forest_ruth" => Box::new(forest_ruth::ForestRuth::new()),
        "dormand_prince" => Box::new(dormand_prince::DormandPrince::new()),
        other => unreachable!("registry entry {other} has no constructor"),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_entry_builds_and_reports_itself() {
        for info in METHODS {
            let method = build::<f64>(info.name).expect("registered");
            assert_eq!(method.info(), *info, "{}", info.name);
            for alias in info.aliases {
                assert_eq!(find(alias).map(|m| m.name), Ok(info.name));
            }
        }
    }

    #[test]
    fn names_are_unique_across_names_and_aliases() {
        let mut all: Vec<&str> = METHODS
            .iter()
            .flat_map(|m| core::iter::once(m.name).chain(m.aliases.iter().copied()))
            .collect();
        let count = all.len();
        all.sort_unstable();
        all.dedup();
        assert_eq!(all.len(), count);
    }

    #[test]
    fn names_are_forgiving_about_case_and_separators() {
        assert_eq!(find("Velocity-Verlet").map(|m| m.name), Ok("velocity_verlet"));
        assert_eq!(find("RK4").map(|m| m.name), Ok("rk4"));
        assert_eq!(find(" dopri5 ").map(|m| m.name), Ok("dormand_prince"));
    }

    #[test]
    fn unknown_name_lists_the_valid_names() {
        let error = build::<f32>("verlett").err().expect("unknown");
        let message = error.to_string();
        assert!(
            message.starts_with("unknown integrator 'verlett'; valid names are: explicit_euler, "),
            "{message}"
        );
        for info in METHODS {
            assert!(message.contains(info.name), "{message} lacks {}", info.name);
        }
    }
}
