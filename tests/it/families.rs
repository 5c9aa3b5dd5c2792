//! The many-obstacle families of issue 26 (`beamfric::check::families`) against the independent
//! 384-bit reference where it is affordable: a few seeds of every family at k = 12 and 40 on
//! 200 elements (`cargo bench --bench reference -- families` scans 200 seeds per family at
//! k ≤ 200). The interior-point guess the condensed method starts from must not change its
//! answer: every DOF to the reference's accuracy, every state right or honestly at its
//! threshold.

use beamfric::check::families::{Family, family_scene};

use crate::reference::check_stable;

#[test]
fn every_family_agrees_with_the_reference_at_small_k() {
    let mut failures = Vec::new();
    for family in Family::ALL {
        for (k, seeds) in [(12usize, 0..3u64), (40, 0..2)] {
            for seed in seeds {
                let scene = family_scene(family, k, seed, 200);
                let name = format!("{} k={k} seed={seed}", family.name());
                if let Err(why) = check_stable(&name, &scene) {
                    failures.push(why.lines().next().unwrap_or_default().to_string());
                }
            }
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

#[test]
fn the_check_passes_every_family_at_k_200() {
    // The scenes of `beamfric check`'s many-obstacle cases at a size a debug build solves
    // quickly: converged, finite, no warning (the check itself runs k = 1000 and 4000).
    for family in Family::ALL {
        let report = beamfric::check::check_family(family, 200);
        assert!(report.passed(), "{}: {:?}", report.case, report.failures);
    }
}
