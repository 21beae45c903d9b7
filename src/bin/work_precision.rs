//! The work-precision study (see `jointwear::paper::studies::work_precision`): writes
//! `data/work_precision.csv`, `figures/work_precision.png` and the default-tolerance rule's
//! `data/work_precision_members.csv`, and prints the error floor and the default tolerance.
//! `work_precision --redraw` only redraws the figure from the CSV; `work_precision --rule` only
//! measures the rule over members (`jointwear::paper::studies::tolerance_rule`).
use jointwear::error::exit_on_error;
use jointwear::io::progress::progress_bar;
use jointwear::paper::studies::tolerance_rule::{
    pick, rule_rows, Reading, RuleRow, RULE_CONTROLS, RULE_FILE,
};
use jointwear::paper::{program, studies};

/// Prints the members' median paired orbit ratio per setting and what the rule picks from
/// `rule` for each step control by each reading.
fn print_picks(rule: &[RuleRow]) {
    for r in rule {
        let (p, i) = (r.orbit_ratio, r.orbit_ratio.interval);
        println!(
            "rtol {:e}, step control {}{}: first-rotation orbit error over the member's own bound's, \
             median {:.3} (interval {:.3}-{:.3}, coverage {:.4}), {:.0} evaluations",
            r.integration.rtol,
            r.integration.control.name(),
            if r.absolute { " (bound)" } else { "" },
            p.median,
            i.lower,
            i.upper,
            i.coverage,
            r.evaluations
        );
    }
    for control in RULE_CONTROLS {
        for reading in Reading::ALL {
            println!(
                "default Dopri5 rtol by the rule, step control {}, {reading:?}: {:?}",
                control.name(),
                pick(rule, control, reading)
            );
        }
    }
}

fn main() {
    let claim = program::one_flag(
        "work_precision",
        "The work-precision study: writes data/work_precision.csv, figures/work_precision.png and \
         the default-tolerance rule's data/work_precision_members.csv",
        &[
            (
                "--redraw",
                "only redraw the figure from data/work_precision.csv",
            ),
            (
                "--rule",
                "only measure the default-tolerance rule over members",
            ),
        ],
    );
    if claim.flags.contains(&"--redraw") {
        exit_on_error(studies::redraw_work_precision());
        let done = "redrew figures/work_precision.png from data/work_precision.csv";
        println!("{}", program::in_root(done));
        return;
    }
    if claim.flags.contains(&"--rule") {
        let bar = progress_bar(0, "members");
        let rule = exit_on_error(rule_rows(&bar));
        bar.finish_and_clear();
        println!("{}", program::in_root(&format!("wrote data/{RULE_FILE}")));
        print_picks(&rule);
        return;
    }
    let bar = progress_bar(0, "work-precision runs");
    let wp = exit_on_error(studies::work_precision(&bar));
    bar.finish_and_clear();
    let done =
        format!("wrote data/work_precision.csv, figures/work_precision.png and data/{RULE_FILE}");
    println!("{}", program::in_root(&done));
    println!("error floor (reference disagreement): {:?}", wp.floor);
    print_picks(&wp.rule);
}
