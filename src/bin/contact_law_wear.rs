//! How much the predicted wear depends on the contact law: the standard and the 0.5 mm case
//! (and Table 3's other cases, steady) as ensembles under every stiffness and every
//! dissipation law, `data/contact_law_wear.csv` and `figures/contact_law_wear.png`. See
//! `jointwear::paper::studies::contact_law_wear`. `--table3` also runs Table 3's other three
//! cases (30 and 600 r/min, 0.2 mm) steady under every law: several times longer. `--redraw`
//! only redraws the figure from the CSV.
use jointwear::error::exit_on_error;
use jointwear::io::progress::progress_bar;
use jointwear::paper::golden::Golden;
use jointwear::paper::program;
use jointwear::paper::provenance::check;
use jointwear::paper::studies::contact_law_wear::{
    contact_law_wear_study, draw_law_wear, pooled, read_law_wear, LAW_WEAR_FIGURE, LAW_WEAR_FILE,
    PROVENANCE, RUN_FAILED, TABLE3_FLAG,
};
use jointwear::Error;

fn main() {
    let claim = program::one_flag(
        "contact_law_wear",
        "How much the predicted wear depends on the contact law: writes data/contact_law_wear.csv \
         and figures/contact_law_wear.png",
        &[
            ("--redraw", "only redraw the figure from the CSV"),
            (
                TABLE3_FLAG,
                "also run Table 3's other cases steady under every law",
            ),
        ],
    );
    let clock = std::time::Instant::now();
    if claim.flags.contains(&"--redraw") {
        // the figure shows the study's numbers: only this checkout's
        exit_on_error(check(&[&PROVENANCE]));
        let Some(rows) = read_law_wear() else {
            return exit_on_error(Err(Error::invalid(
                "--redraw",
                format!("data/{LAW_WEAR_FILE}"),
                "a file of this layout: it is missing or of another layout; run `cargo run \
                 --release --bin contact_law_wear` first",
            )));
        };
        exit_on_error(draw_law_wear(&rows));
        let done = format!("redrew figures/{LAW_WEAR_FIGURE} from data/{LAW_WEAR_FILE}");
        println!("{}", program::in_root(&done));
        return;
    }
    let golden = exit_on_error(Golden::load());
    let bar = progress_bar(0, "ensemble members");
    let table3 = claim.flags.contains(&TABLE3_FLAG);
    let rows = exit_on_error(contact_law_wear_study(table3, &golden, &bar));
    bar.finish_and_clear();
    for r in rows.iter().filter(|r| r.quantity == RUN_FAILED) {
        println!("{} on {}: could not run: {}", r.pair(), r.case, r.error);
    }
    println!(
        "deepest wear after the scene's rotations (µm, mean ± sd over members; p against the \
         paper's law, raw and Holm-adjusted over the laws):"
    );
    for case in ["standard", "clearance_0.5mm"] {
        for r in pooled(&rows, case, "deepest_wear").into_iter().flatten() {
            println!(
                "{case:>16} {:>36}: {:.4} ± {:.4} (p = {:.1e}, Holm {:.1e})",
                r.pair(),
                r.mean * 1e6,
                r.sd * 1e6,
                r.p,
                r.p_holm
            );
        }
    }
    let done = format!("wrote data/{LAW_WEAR_FILE} and figures/{LAW_WEAR_FIGURE}");
    println!(
        "{} in {:.0} s",
        program::in_root(&done),
        clock.elapsed().as_secs_f64()
    );
}
