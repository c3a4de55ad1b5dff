//! One file per method. Each opens with its update formula, order, cost and
//! stability, then its registry entry and implementation.

pub mod adams_bashforth;
pub mod adams_bashforth2;
pub mod adams_bashforth3;
pub mod adams_bashforth4;
pub mod beeman;
pub mod dormand_prince;
pub mod explicit_euler;
pub mod exponential_euler;
pub mod forest_ruth;
pub mod heun;
pub mod implicit_drag_euler;
pub mod implicit_euler;
pub mod leapfrog;
pub mod midpoint;
pub mod newmark_beta;
pub mod position_verlet;
pub mod predictor_corrector_euler;
pub mod rk4;
pub mod semi_implicit_euler;
pub mod trapezoidal;
pub mod velocity_verlet;
