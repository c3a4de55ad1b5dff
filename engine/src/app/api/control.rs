//! Controls: what a viewer changes about a run (pause, single step, time
//! scale, rate, integrators, restart), one type for the window's keys, the
//! control panel and tests alike.
//!
//! The runners apply controls in one place, between frames, before the
//! frame's steps: always at a tick boundary, never in the middle of a
//! frame. The panel only *returns* the controls chosen in it (it reads the
//! source and cannot change it). A [`GameSession`](crate::app::GameSession)
//! records the controls that change the simulation (integrator switches)
//! with the tick they came before, so a replay repeats them there.

use crate::clock::{ClockError, FixedClock, Rate};
use tickwork_integrators::{METHODS, UnknownMethod};

/// A control a viewer applies between frames.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Control {
    /// Pause or resume (P, Space in a scene).
    TogglePause,
    /// While paused, run exactly one fixed step (Period).
    SingleStep,
    /// Double the time scale, up to 16 (`+`).
    Faster,
    /// Halve the time scale, down to 1/16 (`-`).
    Slower,
    /// Set the time scale (the panel offers 1/16 to 16; the clock accepts
    /// what its `time_scale` range allows and refuses the rest by name).
    TimeScale(f64),
    /// Set the fixed steps per second (the panel).
    Rate(f64),
    /// Switch every switchable world to the registry's next integrator (Tab).
    NextIntegrator,
    /// Switch every switchable world to the registry's integrator number
    /// `n` (keys 1-9 are 0-8).
    Integrator(usize),
    /// Switch the world at `world` (its place on the stage) to the
    /// registry's integrator number `method` (the panel).
    WorldIntegrator {
        /// The world's place on the stage, from 0.
        world: usize,
        /// The integrator's place in the registry, from 0.
        method: usize,
    },
    /// Back to the initial state (F5, R in a scene).
    Reset,
}

/// Slowest and fastest time scales the `-`/`+` keys reach.
const TIME_SCALES: [f64; 9] = [0.0625, 0.125, 0.25, 0.5, 1.0, 2.0, 4.0, 8.0, 16.0];

/// The next time scale up (`faster`) or down from `scale` in [`TIME_SCALES`],
/// or `scale` itself at either end.
pub(crate) fn next_time_scale(scale: f64, faster: bool) -> f64 {
    let next = if faster {
        TIME_SCALES.iter().find(|&&s| s > scale * 1.0001)
    } else {
        TIME_SCALES.iter().rev().find(|&&s| s < scale * 0.9999)
    };
    next.copied().unwrap_or(scale)
}

/// Applies the clock's controls (pause, single step, time scale, rate) to
/// `clock`; returns whether `control` was one of them.
///
/// # Errors
/// [`ClockError`] for a time scale or rate the clock refuses (the message
/// names the value and the accepted range).
pub(crate) fn clock_control(clock: &mut FixedClock, control: Control) -> Result<bool, ClockError> {
    match control {
        Control::TogglePause if clock.is_paused() => clock.resume(),
        Control::TogglePause => clock.pause(),
        Control::SingleStep => {
            clock.single_step();
        }
        Control::Faster | Control::Slower => {
            clock.set_time_scale(next_time_scale(clock.config().time_scale, control == Control::Faster))?;
        }
        Control::TimeScale(scale) => clock.set_time_scale(scale)?,
        Control::Rate(hz) => clock.set_rate(Rate::hz_f64(hz)?),
        Control::NextIntegrator | Control::Integrator(_) | Control::WorldIntegrator { .. } | Control::Reset => {
            return Ok(false);
        }
    }
    Ok(true)
}

/// The integrator `control` gives the world at `world` that now runs
/// `current`: `None` if it leaves that world alone (not an integrator
/// control, another world's, or the method it already runs). A world on
/// the GPU (`gpu`) is offered only the GPU step's methods: Tab skips the
/// others, and a number picking one is ignored, saying so.
///
/// # Errors
/// [`UnknownMethod`] for a registry number past the last method.
pub(crate) fn chosen_integrator(
    control: Control,
    world: usize,
    current: &str,
    gpu: bool,
) -> Result<Option<&'static str>, UnknownMethod> {
    let offered = |name: &str| !gpu || crate::gpu_step::takes_method(name);
    let by_number = |n: usize| {
        METHODS
            .get(n)
            .map(|m| m.name)
            .ok_or_else(|| UnknownMethod::new(&format!("#{}", n + 1)))
    };
    let chosen = match control {
        Control::NextIntegrator => {
            let index = METHODS.iter().position(|m| m.name == current).map_or(0, |i| i + 1);
            let next = (0..METHODS.len())
                .map(|k| METHODS[(index + k) % METHODS.len()].name)
                .find(|&name| offered(name));
            match next {
                Some(name) => name,
                None => return Ok(None),
            }
        }
        Control::Integrator(n) => by_number(n)?,
        Control::WorldIntegrator { world: w, method } => {
            let name = by_number(method)?;
            if w != world {
                return Ok(None);
            }
            name
        }
        _ => return Ok(None),
    };
    if !offered(chosen) {
        crate::say!("tickwork: the GPU step has no method \"{chosen}\" (it stays on the CPU); the switch is ignored");
        return Ok(None);
    }
    Ok((chosen != current).then_some(chosen))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn integrator_controls_pick_by_number_in_turn_and_per_world() {
        let first = METHODS[0].name;
        let last = METHODS[METHODS.len() - 1].name;
        assert_eq!(
            chosen_integrator(Control::NextIntegrator, 0, last, false),
            Ok(Some(first))
        );
        assert_eq!(
            chosen_integrator(Control::Integrator(0), 3, first, false),
            Ok(None),
            "already"
        );
        let pick = Control::WorldIntegrator { world: 1, method: 0 };
        assert_eq!(chosen_integrator(pick, 0, last, false), Ok(None), "another world's");
        assert_eq!(chosen_integrator(pick, 1, last, false), Ok(Some(first)));
        let error = chosen_integrator(Control::Integrator(99), 0, first, false).expect_err("no method 100");
        assert!(error.to_string().starts_with("unknown integrator '#100'"), "{error}");
        assert_eq!(chosen_integrator(Control::Faster, 0, first, false), Ok(None));
    }

    #[test]
    fn a_gpu_world_is_offered_the_gpu_steps_methods_only() {
        // Tab from semi-implicit Euler, round the registry: the thirteen
        // methods of the GPU step, each once, and none of the others.
        let mut current = "semi_implicit_euler";
        let mut seen = vec![current];
        loop {
            let next = chosen_integrator(Control::NextIntegrator, 0, current, true)
                .expect("a method")
                .expect("another method");
            if next == "semi_implicit_euler" {
                break;
            }
            assert!(!seen.contains(&next), "{next} twice");
            seen.push(next);
            current = next;
        }
        seen.sort_unstable();
        let mut gpu: Vec<&str> = METHODS
            .iter()
            .map(|m| m.name)
            .filter(|name| crate::gpu_step::takes_method(name))
            .collect();
        gpu.sort_unstable();
        assert_eq!(seen, gpu);
        assert_eq!(seen.len(), 13);
        assert!(!seen.contains(&"implicit_euler") && !seen.contains(&"dormand_prince"));
        // A number picking a method the GPU does not take is ignored.
        let implicit = METHODS
            .iter()
            .position(|m| m.name == "implicit_euler")
            .expect("registered");
        assert_eq!(
            chosen_integrator(Control::Integrator(implicit), 0, "rk4", true),
            Ok(None)
        );
        let rk4 = METHODS.iter().position(|m| m.name == "rk4").expect("registered");
        assert_eq!(
            chosen_integrator(Control::Integrator(rk4), 0, "heun", true),
            Ok(Some("rk4"))
        );
    }

    #[test]
    fn the_clock_takes_its_controls_and_refuses_bad_values_by_name() {
        let mut clock = FixedClock::default();
        assert_eq!(clock_control(&mut clock, Control::TimeScale(0.5)), Ok(true));
        assert_eq!(clock.config().time_scale, 0.5);
        assert_eq!(clock_control(&mut clock, Control::Rate(120.0)), Ok(true));
        assert_eq!(clock.config().rate.hz_value(), 120.0);
        assert_eq!(clock_control(&mut clock, Control::Reset), Ok(false));
        let error = clock_control(&mut clock, Control::TimeScale(f64::NAN)).expect_err("NaN");
        assert!(error.to_string().contains("time_scale"), "{error}");
    }
}
