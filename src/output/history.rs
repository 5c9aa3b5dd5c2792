//! The convergence history of `beamfric solve --history` ([`crate::solve::History`]): the
//! `history` object of the JSON document and the CSV table, one row per iterate.

use serde_json::{Value, json};

use super::{csv_number, number};
use crate::solve::{History, Solution};

/// The `history` object: the method, its measure (name and words), the units, whether the
/// middle iterates were dropped, and per iterate its number, measure, objective, how many
/// friction DOFs changed state and the forces per obstacle.
pub fn history_json(history: &History) -> Value {
    json!({
        "method": history.method.name(),
        "measure": history.measure.name(),
        "measure_label": history.measure.label(),
        "units": { "measure": "1", "objective": "J", "force": "N", "moment": "N m" },
        "truncated": history.truncated,
        "iterations": history.iterations.iter().map(|record| json!({
            "iteration": record.iteration,
            "measure": number(record.measure),
            "objective": record.objective.map(number),
            "changed": record.changed,
            "forces": record.forces.iter().map(|[force, moment]| json!({
                "force": number(*force),
                "moment": number(*moment),
            })).collect::<Vec<_>>(),
        })).collect::<Vec<_>>(),
    })
}

/// The history as CSV: `iteration`, `measure` (named after the method's measure, e.g.
/// `projected_gradient`), `objective_J`, `changed`, then `force_N_j` and `moment_Nm_j` for every
/// obstacle j from 1. Only the header when the method does not iterate (no history).
pub fn history_csv(solution: &Solution) -> String {
    let obstacles = solution.obstacles.len();
    let measure = solution
        .history
        .as_ref()
        .map_or("measure".to_string(), |h| {
            h.measure.name().replace('-', "_")
        });
    let mut header = vec![
        "iteration".to_string(),
        measure,
        "objective_J".into(),
        "changed".into(),
    ];
    for j in 1..=obstacles {
        header.push(format!("force_N_{j}"));
        header.push(format!("moment_Nm_{j}"));
    }
    let mut writer = csv::Writer::from_writer(Vec::new());
    let _ = writer.write_record(&header);
    for record in solution.history.iter().flat_map(|h| &h.iterations) {
        let mut row = vec![
            record.iteration.to_string(),
            csv_number(Some(record.measure)),
            csv_number(record.objective),
            record.changed.to_string(),
        ];
        for [force, moment] in &record.forces {
            row.push(csv_number(Some(*force)));
            row.push(csv_number(Some(*moment)));
        }
        let _ = writer.write_record(&row);
    }
    String::from_utf8(writer.into_inner().unwrap_or_default()).unwrap_or_default()
}
