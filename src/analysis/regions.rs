//! Wear regions of a bearing: the one definition every printout, file, figure and claim uses.
//!
//! The wear profile is periodic (sector i centred at (i + 0.5)·360/N deg; the last sector
//! touches the first). A **wear region** is a hump of that profile, found by topographic
//! prominence: a local maximum's prominence is its depth above the higher of the two lowest
//! points that separate it, going either way round, from a deeper point (the deepest sector's
//! is its height above the profile floor, the shallowest sector). A local maximum is a region
//! when its prominence is
//!
//! * at least [`MIN_RELATIVE_PROMINENCE`] of the most prominent region's, and
//! * at least [`MIN_PROMINENCE_OF_HEIGHT`] of its own height above the profile floor.
//!
//! A shoulder or ripple on a hump has a small prominence, so it fails the rules and is no region:
//! the sub-peaks of one hump are merged into it. Regions are listed by prominence, most
//! prominent first, so the first is always the deepest sector.

/// A wear region on the bearing.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Region {
    /// Index of the region's deepest sector.
    pub sector: usize,
    /// Angle of the deepest sector (deg, counter-clockwise from the bearing's +x).
    pub angle_deg: f64,
    /// Wear depth at that sector (m).
    pub depth: f64,
    /// Topographic prominence (m).
    pub prominence: f64,
    /// Full width at half prominence (deg).
    pub width_deg: f64,
}

/// Smallest prominence of a region, as a fraction of the most prominent region's. The
/// four-bar's shoulders of its deepest hump have 6-8 % of its prominence and its distinct third
/// hump 38 %; the sector-scale ripples of the standard case stay below 5 %. 10 % separates
/// those; the four-bar's spiky bands (near 0-50 and 250-340 deg) have humps of 9-21 %, on both
/// sides of it, so it prints 10 regions.
pub const MIN_RELATIVE_PROMINENCE: f64 = 0.10;

/// Smallest prominence of a region, as a fraction of its own height above the profile floor.
/// A bump whose col lies above 85 % of its height is drawn as part of the hump it rides on (a
/// second crest of one hump, or noise on a worn band), not as a hump of its own. Relative to the
/// floor, not to zero wear, so that wear spread evenly around the bearing changes no region.
pub const MIN_PROMINENCE_OF_HEIGHT: f64 = 0.15;

/// The wear regions of a periodic profile `depths` (m, sector i centred at (i + 0.5)·360/N
/// deg), most prominent first; none for fewer than 3 sectors or a flat profile.
pub fn wear_regions(depths: &[f64]) -> Vec<Region> {
    let n = depths.len();
    let floor = depths.iter().cloned().fold(f64::INFINITY, f64::min);
    if n < 3 || depths.iter().all(|&d| d == floor) {
        return Vec::new();
    }
    let width = 360.0 / n as f64;
    let at = |i: isize| depths[i.rem_euclid(n as isize) as usize];
    // A strict order on sectors: deeper, or as deep and earlier. A plateau then has one local
    // maximum (its first sector) and two equally deep humps are one region above the other.
    let above = |j: isize, i: isize| {
        let (a, b) = (at(j), at(i));
        a > b || (a == b && j.rem_euclid(n as isize) < i.rem_euclid(n as isize))
    };
    let mut found: Vec<Region> = Vec::new();
    for i in 0..n as isize {
        if above(i - 1, i) || above(i + 1, i) {
            continue;
        }
        let d = at(i);
        // walk each way until a point above this one (or all around), tracking the lowest point
        let col = |dir: isize| {
            (1..n as isize)
                .map(|k| i + dir * k)
                .take_while(|&j| !above(j, i))
                .map(at)
                .fold(d, f64::min)
        };
        let prominence = d - col(-1).max(col(1));
        let half = d - 0.5 * prominence;
        let extent = |dir: isize| {
            (1..n as isize)
                .take_while(|&k| at(i + dir * k) > half)
                .count() as f64
        };
        found.push(Region {
            sector: i as usize,
            angle_deg: (i as f64 + 0.5) * width,
            depth: d,
            prominence,
            width_deg: (1.0 + extent(-1) + extent(1)).min(n as f64) * width,
        });
    }
    let top = found.iter().map(|r| r.prominence).fold(0.0, f64::max);
    found.retain(|r| {
        r.prominence >= MIN_RELATIVE_PROMINENCE * top
            && r.prominence >= MIN_PROMINENCE_OF_HEIGHT * (r.depth - floor)
    });
    found.sort_by(|a, b| b.prominence.total_cmp(&a.prominence));
    found
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    /// 360 one-degree sectors holding Gaussian humps `(centre deg, height, half-width deg)`.
    fn humps(list: &[(f64, f64, f64)]) -> Vec<f64> {
        (0..360)
            .map(|i| {
                let a = i as f64 + 0.5;
                list.iter()
                    .map(|&(c, h, w)| {
                        let d = ((a - c + 180.0).rem_euclid(360.0)) - 180.0;
                        h * (-(d / w).powi(2)).exp()
                    })
                    .sum()
            })
            .collect()
    }

    fn angles(r: &[Region]) -> Vec<f64> {
        r.iter().map(|r| r.angle_deg).collect()
    }

    #[test]
    fn three_separate_humps_are_three_regions_by_prominence() {
        // centred on sector centres, so no two sectors tie for a top
        let r = wear_regions(&humps(&[
            (50.5, 1.0, 10.0),
            (180.5, 3.0, 10.0),
            (300.5, 2.0, 10.0),
        ]));
        assert_eq!(angles(&r), vec![180.5, 300.5, 50.5]);
        // Gaussian exp(-(x/10)²): full width at half maximum 2·sqrt(ln 2)·10 = 16.65 deg; the
        // profile is sampled per degree, so the width is right to one sector
        assert!((r[0].width_deg - 16.65).abs() <= 1.0, "{:?}", r[0]);
        // the humps' tails add < 1e-40 at the other humps' centres
        assert_relative_eq!(r[0].depth, 3.0, max_relative = 1e-12);
        assert_relative_eq!(r[0].prominence, 3.0, max_relative = 1e-12);
    }

    #[test]
    fn a_broad_hump_with_ripples_is_one_region() {
        // ripples of 6 % of the hump peak to peak every 12 deg make local maxima on its flanks
        // and crest (and on the unworn side)
        let mut d = humps(&[(120.5, 1.0, 40.0)]);
        for (i, x) in d.iter_mut().enumerate() {
            *x += 0.03 * (1.0 + (i as f64 * std::f64::consts::TAU / 12.0).sin());
        }
        let r = wear_regions(&d);
        assert_eq!(r.len(), 1, "{r:?}");
        assert!((r[0].angle_deg - 120.5).abs() <= 6.0, "{r:?}");
    }

    #[test]
    fn a_hump_across_the_seam_is_one_region() {
        let r = wear_regions(&humps(&[(0.0, 1.0, 15.0)]));
        assert_eq!(r.len(), 1, "{r:?}");
        // the two sectors beside 0 deg tie; the earlier (0.5 deg) is the region's
        assert_eq!(r[0].angle_deg, 0.5);
        // FWHM 2·sqrt(ln 2)·15 = 25 deg, counted across the seam
        assert!((r[0].width_deg - 25.0).abs() <= 1.0, "{:?}", r[0]);
    }

    #[test]
    fn one_percent_noise_on_a_worn_floor_creates_no_region() {
        // a worn floor of 0.5, one hump of 1 above it, and ±1 % of the deepest wear as noise
        // (a fixed pseudo-random sequence, so the test is reproducible)
        let mut d = humps(&[(200.5, 1.0, 12.0)]);
        let mut seed = 12345_u64;
        for x in d.iter_mut() {
            seed = seed
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            let u = (seed >> 11) as f64 / (1u64 << 53) as f64;
            *x += 0.5 + 0.015 * (2.0 * u - 1.0);
        }
        let r = wear_regions(&d);
        assert_eq!(angles(&r).len(), 1, "{r:?}");
        assert!((r[0].angle_deg - 200.5).abs() <= 2.0, "{r:?}");
        assert!(wear_regions(&[0.3; 36]).is_empty());
    }

    #[test]
    fn a_bump_high_on_a_worn_band_is_part_of_it() {
        // a band worn 0.8 deep over 100-220 deg, a crest of 1 at 130.5 deg, and a bump rising
        // 0.12 above the band at 190.5 deg: its prominence is 12 % of the crest's, enough for
        // MIN_RELATIVE_PROMINENCE, but 13 % of its height, so the second rule merges it into
        // the band's region (checked: dropping that rule fails this test)
        let tent = |i: usize, c: f64, h: f64, half: f64| {
            h * (1.0 - (i as f64 + 0.5 - c).abs() / half).max(0.0)
        };
        let d: Vec<f64> = (0..360)
            .map(|i| {
                let band = if (100..=220).contains(&i) { 0.8 } else { 0.0 };
                band + tent(i, 130.5, 0.2, 10.0) + tent(i, 190.5, 0.12, 5.0)
            })
            .collect();
        let r = wear_regions(&d);
        assert_eq!(angles(&r), vec![130.5], "{r:?}");
    }

    #[test]
    fn a_deep_shoulder_ranks_below_a_distinct_smaller_hump() {
        // the four-bar's pattern: a shoulder on the deepest hump is deeper than the distinct
        // hump elsewhere, so ranking local maxima by depth (the rule this replaced) listed the
        // shoulder second and the distinct hump third or not at all (checked: with the old rule,
        // 5 % of the deepest depth and ranked by depth, this test fails)
        // (a bump of 0.15 on the flank of a broad hump, 14 deg from its crest, is a shoulder
        // 0.954 deep of prominence 0.077: above the old 5 % of the deepest, below 10 %)
        let d = humps(&[(150.5, 1.0, 30.0), (250.5, 0.5, 10.0), (136.5, 0.15, 1.5)]);
        let r = wear_regions(&d);
        assert_eq!(angles(&r), vec![150.5, 250.5], "{r:?}");
        // the broad hump's tail lifts the col between the two by 0.003
        assert_relative_eq!(r[1].prominence, 0.5, max_relative = 1e-2);
    }
}
