//! What the standard-scene examples share: the trajectory named on their command line.

use jointwear::simulation::ensemble::{member_simulation, EnsembleSettings};
use jointwear::simulation::Scene;
use jointwear::simulation::Simulation;

/// The run of `scene` that the command line's `[MEMBER SEED]` names: no arguments, the
/// unperturbed default trajectory; else ensemble member MEMBER of seed SEED, as
/// `jointwear run --member MEMBER --seed SEED` runs it.
pub fn named_trajectory(scene: &Scene) -> Result<Simulation, Box<dyn std::error::Error>> {
    let args: Vec<u64> = std::env::args()
        .skip(1)
        .map(|a| a.parse())
        .collect::<Result<_, _>>()
        .map_err(|e| format!("arguments are MEMBER SEED (two integers): {e}"))?;
    Ok(match args[..] {
        [] => Simulation::start(scene)?,
        [member, seed] => {
            let member = member as usize;
            let ensemble = EnsembleSettings {
                members: member + 1,
                seed,
                ..EnsembleSettings::default()
            };
            member_simulation(scene, &scene.run, &ensemble, member)?
        }
        _ => return Err("arguments are MEMBER SEED, or none".into()),
    })
}
