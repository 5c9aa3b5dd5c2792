//! `beamfric export`: the discrete problem of a scene ([`DiscreteProblem`]) written as plain
//! files a student's own code can read — A, b, B and g of (38)–(49) in Matrix Market, all of
//! them in one JSON file, the mesh as CSV and a README.md of the conventions. Nothing is
//! replaced without `force`; every file is written atomically ([`crate::scene::write_atomic`]:
//! a temporary file in the directory, synced, renamed).

use std::path::{Path, PathBuf};

use super::ExchangeError;
use super::discrete::{DiscreteProblem, g17};
use crate::fem::Mesh;
use crate::model::Problem;
use crate::output::json_text;
use crate::scene::SaveError;

/// The files of an export, in the order they are written.
pub const EXPORT_FILES: [&str; 8] = [
    "stiffness_A.mtx",
    "load_b.mtx",
    "friction_B.mtx",
    "thresholds_g.mtx",
    "problem.json",
    "nodes.csv",
    "elements.csv",
    "README.md",
];

/// What names the exported scene in the files.
#[derive(Debug, Clone, Copy)]
pub struct ExportedScene<'a> {
    /// The scene's title.
    pub title: &'a str,
    /// A file path or `preset NAME`.
    pub source: &'a str,
    /// How to name the scene on a command line (`--scene …`, `--elements …`), for the README.
    pub command_scene: &'a str,
}

/// Writes the export of `problem` on `mesh` into `dir` (created if missing) and returns the
/// paths written. With `force == false` an existing file of the export is an error before
/// anything is written. When a write fails (a full disk, a directory in a file's place), the
/// files this call created and the directories it created are removed again: a failed
/// export leaves what was there before (with `force`, a file it had already replaced stays
/// replaced, complete).
pub fn export(
    problem: &Problem,
    mesh: &Mesh,
    scene: ExportedScene,
    dir: &Path,
    force: bool,
) -> Result<Vec<PathBuf>, ExchangeError> {
    let paths: Vec<PathBuf> = EXPORT_FILES.iter().map(|name| dir.join(name)).collect();
    let existed: Vec<bool> = paths
        .iter()
        .map(|p| std::fs::symlink_metadata(p).is_ok())
        .collect();
    if !force && existed.contains(&true) {
        let existing = paths.iter().zip(&existed).filter(|(_, e)| **e);
        return Err(ExchangeError::Exists(
            existing.map(|(p, _)| p.clone()).collect(),
        ));
    }
    let created_dirs = create_dirs(dir).map_err(|e| ExchangeError::io(dir, e))?;
    let discrete = DiscreteProblem::new(problem, mesh);
    let texts = file_texts(&discrete, problem, scene);
    for (written, (path, text)) in paths.iter().zip(&texts).enumerate() {
        if let Err(e) = crate::scene::write_atomic(path, text.as_bytes(), force) {
            // The failed file too: a failure after its rename (syncing the directory) leaves
            // it in place.
            let created = paths[..=written].iter().zip(&existed).filter(|(_, e)| !**e);
            for (file, _) in created {
                let _ = std::fs::remove_file(file);
            }
            remove_dirs(&created_dirs);
            return Err(match e {
                SaveError::Exists(p) => ExchangeError::Exists(vec![p]),
                SaveError::Io(p, e) => ExchangeError::io(&p, e),
                other => ExchangeError::Io {
                    path: path.clone(),
                    action: "write",
                    reason: other.to_string(),
                },
            });
        }
    }
    Ok(paths)
}

/// Creates `dir` one component at a time and returns the directories this call created, in
/// order (a path with `..` or symbolic links in it can name an existing directory below a
/// new one, so only what `create_dir` itself made counts as created). On an error, what it
/// created is removed again.
fn create_dirs(dir: &Path) -> std::io::Result<Vec<PathBuf>> {
    let mut created = Vec::new();
    let mut prefix = PathBuf::new();
    for component in dir.components() {
        prefix.push(component);
        match std::fs::create_dir(&prefix) {
            Ok(()) => created.push(prefix.clone()),
            Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => {}
            Err(e) => {
                remove_dirs(&created);
                return Err(e);
            }
        }
    }
    Ok(created)
}

/// Removes the directories `created` (as [`create_dirs`] returned them), the last first, each
/// only if it is empty: whatever else is in them stays.
fn remove_dirs(created: &[PathBuf]) {
    for dir in created.iter().rev() {
        let _ = std::fs::remove_dir(dir);
    }
}

/// The texts of [`EXPORT_FILES`], in that order.
fn file_texts(discrete: &DiscreteProblem, problem: &Problem, scene: ExportedScene) -> Vec<String> {
    let title = scene.title;
    vec![
        discrete.stiffness_mtx(title),
        DiscreteProblem::vector_mtx(
            &discrete.load,
            title,
            "b of (38)-(39): b_i = F(phi_i) = integral of f phi_i [N for u rows, N m for u' rows]",
        ),
        discrete.friction_mtx(title),
        DiscreteProblem::vector_mtx(
            &discrete.thresholds,
            title,
            "g of (45): g1 [N], g2 [N m] per obstacle; |lambda_r| <= g_r",
        ),
        json_text(&discrete.to_json(title, scene.source)),
        nodes_csv(discrete),
        elements_csv(discrete),
        readme(discrete, problem, scene),
    ]
}

/// node, x [m] and the 0-based indices of its two DOFs (empty at the clamped ends).
fn nodes_csv(discrete: &DiscreteProblem) -> String {
    let last = discrete.nodes.len() - 1;
    let mut text = String::from("node,x_m,u_dof,slope_dof,obstacle\n");
    for (node, &x) in discrete.nodes.iter().enumerate() {
        let dofs = if node == 0 || node == last {
            ",".to_string()
        } else {
            format!("{},{}", 2 * (node - 1), 2 * (node - 1) + 1)
        };
        let obstacle = discrete
            .obstacle_nodes
            .iter()
            .position(|&o| o == node)
            .map_or(String::new(), |j| (j + 1).to_string());
        text.push_str(&format!("{node},{},{dofs},{obstacle}\n", g17(x)));
    }
    text
}

/// element, its two nodes, length [m] and E·J [N m²].
fn elements_csv(discrete: &DiscreteProblem) -> String {
    let mut text = String::from("element,first_node,last_node,length_m,bending_stiffness_Nm2\n");
    for (e, (h, ej)) in discrete
        .element_lengths
        .iter()
        .zip(&discrete.element_bending_stiffness)
        .enumerate()
    {
        text.push_str(&format!("{e},{e},{},{},{}\n", e + 1, g17(*h), g17(*ej)));
    }
    text
}

/// The README.md of an export: what is where, and the conventions.
fn readme(discrete: &DiscreteProblem, problem: &Problem, scene: ExportedScene) -> String {
    let n = discrete.nodes.len() - 1;
    let k = problem.obstacles.len();
    let big_n = discrete.unknowns;
    let obstacles: String = problem
        .obstacles
        .iter()
        .zip(&discrete.obstacle_nodes)
        .enumerate()
        .map(|(j, (o, &node))| {
            format!(
                "| {} | {} | {node} | {}, {} | {} | {} |\n",
                j + 1,
                g17(o.x),
                2 * (node - 1),
                2 * (node - 1) + 1,
                g17(o.sliding_threshold),
                g17(o.swivel_threshold)
            )
        })
        .collect();
    format!(
        include_str!("export_readme.md"),
        title = scene.title,
        source = scene.source,
        command_scene = scene.command_scene,
        n = n,
        n_minus_1 = n - 1,
        big_n = big_n,
        k = k,
        two_k = 2 * k,
        nnz = discrete.stiffness_lower.len(),
        obstacles = obstacles,
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn only_the_directories_an_export_created_are_removed_and_only_if_empty() {
        let base = tempfile::tempdir().unwrap();
        let dir = base.path().join("a").join("b").join("c");
        let created = create_dirs(&dir).unwrap();
        assert_eq!(created.len(), 3);
        remove_dirs(&created);
        assert!(
            !base.path().join("a").exists(),
            "every created level removed"
        );
        assert!(base.path().exists(), "the existing parent stays");

        // Someone else's file in a created level keeps that level (and those above it).
        let created = create_dirs(&dir).unwrap();
        std::fs::write(base.path().join("a").join("b").join("theirs"), "x").unwrap();
        remove_dirs(&created);
        assert!(!dir.exists());
        assert!(base.path().join("a").join("b").join("theirs").exists());

        // Nothing created: nothing removed.
        assert!(create_dirs(base.path()).unwrap().is_empty());
    }

    #[test]
    fn a_path_through_dot_dot_never_removes_a_directory_that_was_there() {
        // new/../out names the existing (empty) out below a new directory: only new and
        // what is created inside out count as created.
        let base = tempfile::tempdir().unwrap();
        std::fs::create_dir(base.path().join("out")).unwrap();
        let dir = base.path().join("new").join("..").join("out").join("a");
        let created = create_dirs(&dir).unwrap();
        assert_eq!(created.len(), 2, "{created:?}");
        remove_dirs(&created);
        assert!(
            base.path().join("out").is_dir(),
            "the user's directory stays"
        );
        assert!(!base.path().join("out").join("a").exists());
        assert!(!base.path().join("new").exists());

        // A creation that fails half-way (a file where a directory should be) removes what
        // it had created.
        std::fs::write(base.path().join("file"), "x").unwrap();
        let blocked = base.path().join("new").join("..").join("file").join("x");
        assert!(create_dirs(&blocked).is_err());
        assert!(!base.path().join("new").exists());
        assert!(base.path().join("file").is_file());
    }
}
