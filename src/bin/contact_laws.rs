//! What each contact law does to one impact: the achieved against the given restitution of
//! every stiffness law with every dissipation law, `data/contact_laws_restitution.csv`, and
//! `figures/contact_laws.png`. See `jointwear::paper::studies::contact_laws`.
use jointwear::error::exit_on_error;
use jointwear::laws::contact::{DissipationLaw, StiffnessLaw};
use jointwear::paper::studies::contact_laws::contact_laws_study;

fn main() {
    let _claim = jointwear::paper::program::flags(
        "contact_laws",
        "What each contact law does to one impact: writes data/contact_laws_restitution.csv and figures/contact_laws.png",
        &[],
    );
    let sweep = exit_on_error(contact_laws_study());
    println!("largest |achieved - given| restitution over c_e in [0.1, 0.99], per law pair:");
    print!("{:>12}", "");
    for d in DissipationLaw::ALL {
        print!(" {:>19}", d.name());
    }
    println!();
    for s in StiffnessLaw::ALL {
        print!("{:>12}", s.name());
        for d in DissipationLaw::ALL {
            let worst = (sweep.iter())
                .filter(|i| i.stiffness == s && i.dissipation == d)
                .map(|i| (i.achieved - i.given).abs())
                .fold(0.0, f64::max);
            print!(" {worst:>19.4}");
        }
        println!();
    }
    println!(
        "{}",
        jointwear::paper::program::in_root(
            "wrote data/contact_laws_restitution.csv and figures/contact_laws.png"
        )
    );
}
