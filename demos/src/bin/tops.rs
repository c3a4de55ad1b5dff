//! Spinning boxes and the intermediate-axis (Dzhanibekov) flip, integrated
//! by two first-order angular methods side by side: quaternion Euler
//! (left) and the exponential map (right). Each side spins one box about
//! its intermediate axis (it flips over and over) and one about its major
//! axis (it spins steadily). Both are first order and step Euler's
//! equations for the angular velocity explicitly, so both drift in energy
//! (shown live); they differ in the rotation: quaternion Euler adds
//! `dt/2 (0, w) q`, which leaves the unit sphere and is renormalised, while
//! the exponential map rotates by exactly `|w| dt` about `w`.

use std::fmt::Write;
use std::process::ExitCode;

use tickwork::prelude::*;

/// Angular methods, side by side, and their x offset (m).
const SIDES: [(&str, f32); 2] = [("quaternion_euler", -2.2), ("exponential_map", 2.2)];

#[derive(Clone)]
struct Tops;

impl Game for Tops {
    fn title(&self) -> &str {
        "tops"
    }

    fn setup(&mut self, stage: &mut Stage, settings: &Settings) -> Result<(), GameError> {
        for (method, x) in SIDES {
            let config = WorldConfig {
                angular_integrator: method.to_owned(),
                seed: settings.seed,
                ..WorldConfig::default()
            };
            let mut world = World::new(config)?;
            // Half extents 0.6 x 0.3 x 0.1: principal moments ordered
            // I_x < I_y < I_z, so y is the intermediate axis.
            let half = Vec3::new(0.6, 0.3, 0.1);
            for (y, spin, colour) in [
                (0.9, Vec3::new(0.0, 5.0, 0.03), [230, 90, 80, 255]),
                (-0.9, Vec3::new(0.03, 0.0, 5.0), [90, 200, 110, 255]),
            ] {
                let mut body = RigidBody::solid_box(1.0, half);
                body.particle.position = Vec3::new(x, y, 0.0);
                body.particle.colour = colour;
                body.angular_velocity = spin;
                world.spawn_rigid(body)?;
            }
            stage.add_world(method, world).fixed_integrator();
        }
        stage.panel = true;
        stage.rate = Rate::hz(120)?;
        stage.camera = Camera::Orbit {
            target: Vec3::ZERO,
            distance: 7.5,
            yaw: 0.0,
            pitch: 20.0,
            fov_y: 45.0,
        };
        Ok(())
    }

    fn draw(&self, stage: &Stage, _alpha: f32, draw: &mut Draw) -> Result<(), GameError> {
        let t = stage.worlds.first().map_or(0.0, |w| w.world.time());
        let _ = writeln!(
            draw.hud,
            "Top: intermediate-axis flip; bottom: steady spin; t = {t:.1} s"
        );
        for shown in &stage.worlds {
            draw.colour(shown.colour);
            let _ = writeln!(
                draw.hud,
                "{}: energy error {:+.2e}",
                shown.world.angular_integrator().info().title,
                shown.energy.latest()
            );
        }
        Ok(())
    }

    fn outcome(&self, stage: &Stage) -> Option<String> {
        let errors: Vec<String> = stage
            .worlds
            .iter()
            .map(|w| format!("{} {:+.3e}", w.label, w.energy.latest()))
            .collect();
        Some(format!("energy error: {}", errors.join(", ")))
    }
}

fn main() -> ExitCode {
    exit_code(run(Tops, RunOptions::from_args()))
}
