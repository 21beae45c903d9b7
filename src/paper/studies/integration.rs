//! An integration setting (method, tolerances, step cap) and how it is applied to a scene:
//! the variable of the work-precision and accuracy-dependence studies.

use super::work_precision::wp_max_step;
use crate::ode::Method;
use crate::scene::{MethodSpec, RunSpec, SceneFile, StepControlSpec};

/// `atol` over `rtol` of the adaptive settings the studies compare: one atol for every
/// controlled state component (m, rad, m/s, rad/s).
pub const ATOL_PER_RTOL: f64 = 1e-3;

/// An integration setting applied to a scene.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Integration {
    /// The integrator.
    pub method: Method,
    /// Relative tolerance (unused by fixed-step methods).
    pub rtol: f64,
    /// Absolute tolerance in state units (m, rad, m/s, rad/s).
    pub atol: f64,
    /// Largest step (s).
    pub max_step: f64,
    /// Step-size controller of an adaptive method (the I controller for a fixed step).
    pub control: StepControlSpec,
}

impl Integration {
    /// Adaptive `method` at `rtol`, `atol = `[`ATOL_PER_RTOL`]`·rtol`, with the work-precision
    /// step cap of the method ([`wp_max_step`]) and the I controller.
    pub fn adaptive(method: Method, rtol: f64) -> Integration {
        Integration {
            method,
            rtol,
            atol: ATOL_PER_RTOL * rtol,
            max_step: wp_max_step(method),
            control: StepControlSpec::I,
        }
    }

    /// This adaptive setting with the step control `control`.
    pub const fn with_control(self, control: StepControlSpec) -> Integration {
        Integration { control, ..self }
    }

    /// Classical RK4 with a fixed `step` (s); tolerances unused.
    pub fn rk4(step: f64) -> Integration {
        Integration {
            method: Method::Rk4 { step },
            rtol: 1.0,
            atol: 1.0,
            max_step: step,
            control: StepControlSpec::I,
        }
    }

    /// The integration a scene's `run` asks for ([`Integration::apply`] read back).
    pub fn of(run: &RunSpec) -> Integration {
        let method = match run.method {
            MethodSpec::Dopri5 => Method::Dopri5,
            MethodSpec::Dop853 => Method::Dop853,
            MethodSpec::Rk4 => Method::Rk4 {
                step: run.fixed_step_s.unwrap_or(run.max_step_s),
            },
        };
        Integration {
            method,
            rtol: run.rtol,
            atol: run.atol,
            max_step: run.max_step_s,
            control: run.step_control,
        }
    }

    /// Sets the scene's run to this integration.
    pub fn apply(&self, f: &mut SceneFile) {
        let run = &mut f.run;
        run.method = match self.method {
            Method::Dopri5 => MethodSpec::Dopri5,
            Method::Dop853 => MethodSpec::Dop853,
            Method::Rk4 { step } => {
                run.fixed_step_s = Some(step);
                MethodSpec::Rk4
            }
        };
        run.rtol = self.rtol;
        run.atol = self.atol;
        run.max_step_s = self.max_step;
        run.step_control = self.control;
    }

    /// Method name as in the CSV files.
    pub fn method_name(&self) -> &'static str {
        match self.method {
            Method::Dopri5 => "dopri5",
            Method::Dop853 => "dop853",
            Method::Rk4 { .. } => "rk4",
        }
    }

    /// `"rtol=1e-6 max_step=1e-3"`, `"rtol=2.5e-7 max_step=1e-3 step_control=pi42"` (a
    /// controller other than the I controller is named) or `"h=1e-5"`.
    pub fn setting(&self) -> String {
        match (self.method, self.control) {
            (Method::Rk4 { step }, _) => format!("h={step:e}"),
            (_, StepControlSpec::I) => format!("rtol={:e} max_step={:e}", self.rtol, self.max_step),
            (_, c) => format!(
                "rtol={:e} max_step={:e} step_control={}",
                self.rtol,
                self.max_step,
                c.name()
            ),
        }
    }
}
