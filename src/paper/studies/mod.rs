//! Numerical studies of the integration itself: how error trades against run time
//! ([`work_precision`](mod@work_precision)), whether the paper's results depend on integration
//! accuracy ([`accuracy`]), whether Table 3's ensembles need the scenes' tolerance
//! ([`ensemble_tolerance`](mod@ensemble_tolerance)), which tolerance the scenes take
//! ([`tolerance_rule`]), and whether stiff and extreme cases run to completion
//! ([`stability`](mod@stability)), and what each contact law does to one impact
//! ([`contact_laws`]), and how much the predicted wear depends on the contact law
//! ([`contact_law_wear`]) and on the bearing's sector count ([`sector_resolution`]). Each study
//! writes `data/<study>.csv` (and a figure where it has one) atomically and returns what it
//! measured, which the report (sections 5 and 6 of `paper.md`) reads; the `src/bin/` programs
//! only call them.
//!
//! Owns: the studies' shared notion of an integration setting ([`Integration`]).

pub mod accuracy;
pub mod contact_law_wear;
pub mod contact_laws;
pub mod ensemble_tolerance;
pub mod integration;
pub mod sector_resolution;
pub mod stability;
pub mod tolerance_rule;
pub mod work_precision;
pub mod work_precision_figure;

pub use accuracy::{
    accuracy_dependence, accuracy_settings, AccuracyDependence, AccuracyRow, Finding, Setting,
    Subject, ACCURACY_HEADER,
};
pub use ensemble_tolerance::{ensemble_tolerance, ToleranceRow};
pub use integration::Integration;
pub use stability::{
    stability, stability_case, stability_cases, StabilityRow, STABILITY_HEADER,
    STABILITY_MAX_STEPS, STABILITY_ROTATIONS,
};
pub use work_precision::{
    work_precision, work_precision_settings, wp_max_step, EnsembleWearError, Errors, WorkPrecision,
    WorkRow, FORCE_BOUND, REFERENCE, SECOND_REFERENCE, WP_ENSEMBLE_MAX_EVALUATIONS, WP_MAX_STEP,
    WP_MEMBERS,
};
pub use work_precision_figure::redraw_work_precision;
