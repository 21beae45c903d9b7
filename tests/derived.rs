//! What `jointwear run` derives from a run and prints and saves: the wear regions (one
//! definition, `jointwear::analysis::regions`) and the maxima with the window they are taken over.

mod common;

use common::{jointwear, s, stdout, temp_dir};
use jointwear::analysis::regions::{MIN_PROMINENCE_OF_HEIGHT, MIN_RELATIVE_PROMINENCE};
use jointwear::scene::scene_path;
use std::fs;
use std::path::Path;

fn json(path: &Path) -> serde_json::Value {
    serde_json::from_str(&fs::read_to_string(path).unwrap()).unwrap()
}

/// The four-bar's wear profile has one deep hump with two shoulders and two smaller distinct
/// humps: the printout names the three humps, and `summary.json` lists every region by
/// prominence, each passing both rules. Failed with regions ranked by depth (printed 152.5,
/// 144.5 and 160.5 deg, two shoulders of one hump).
#[test]
fn run_prints_the_most_prominent_distinct_wear_regions() {
    let dir = temp_dir("derived", "fourbar");
    let out = dir.join("out");
    let scene = scene_path("fourbar");
    let o = jointwear(&["run", s(&scene), "--out", s(&out)]);
    assert!(o.status.success());
    let text = stdout(&o);
    let summary = json(&out.join("summary.json"));
    let regions = summary["joints"][0]["wear_regions"].as_array().unwrap();
    let field = |r: &serde_json::Value, k: &str| r[k].as_f64().unwrap();
    assert!(regions.len() >= 3, "{regions:?}");
    let top = field(&regions[0], "prominence_m");
    let floor = summary["joints"][0]["max_wear_depth_m"].as_f64().unwrap() - top;
    for pair in regions.windows(2) {
        assert!(field(&pair[0], "prominence_m") >= field(&pair[1], "prominence_m"));
    }
    for r in regions {
        let p = field(r, "prominence_m");
        assert!(p >= MIN_RELATIVE_PROMINENCE * top, "{r}");
        assert!(
            p >= MIN_PROMINENCE_OF_HEIGHT * (field(r, "depth_m") - floor),
            "{r}"
        );
    }
    let printed: Vec<f64> = regions[..3].iter().map(|r| field(r, "angle_deg")).collect();
    for a in &printed {
        assert!(
            text.contains(&format!("wear region at {a:6.1} deg")),
            "{text}"
        );
    }
    // distinct humps: no two of the three printed within a hump's half-width (15 deg) of each
    // other, as a shoulder is of its crest
    for (i, a) in printed.iter().enumerate() {
        for b in &printed[i + 1..] {
            let d = (a - b).rem_euclid(360.0);
            assert!(d.min(360.0 - d) > 15.0, "{printed:?}");
        }
    }
    fs::remove_dir_all(&dir).unwrap();
}
