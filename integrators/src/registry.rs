//! Every method by name: the lookup behind `--integrator NAME` and the
//! table `tickwork integrators` prints (the list itself is the `methods!`
//! invocation in `lib.rs`).

use core::fmt;

use crate::integrator::{Integrator, MethodInfo};
use crate::vector::Vector;
use crate::{METHODS, construct};

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

/// The one rule by which a given name matches a registered one, in both
/// registries (this one and [`angular`](crate::angular)): case-insensitive,
/// with `-`, `_` and spaces ignored (`"Velocity-Verlet"`, `"quaternionEuler"`).
pub(crate) fn same_name(given: &str, known: &str) -> bool {
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
    construct(find(name)?.name).ok_or_else(|| UnknownMethod::new(name))
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
    fn no_name_or_alias_means_two_methods_in_either_registry() {
        // Every name and alias of both registries, compared by the one
        // matching rule: `euler` or `rk4` may not mean a linear method here
        // and an angular one there.
        let angular = crate::angular::ANGULAR_METHODS.iter().flat_map(|m| {
            core::iter::once(m.name)
                .chain(m.aliases.iter().copied())
                .map(move |n| (n, m.name))
        });
        let linear = METHODS.iter().flat_map(|m| {
            core::iter::once(m.name)
                .chain(m.aliases.iter().copied())
                .map(move |n| (n, m.name))
        });
        let all: Vec<(&str, &str)> = linear.chain(angular).collect();
        for (i, (a, owner_a)) in all.iter().enumerate() {
            for (b, owner_b) in &all[i + 1..] {
                assert!(
                    !same_name(a, b),
                    "'{a}' ({owner_a}) and '{b}' ({owner_b}) are the same name"
                );
            }
        }
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
