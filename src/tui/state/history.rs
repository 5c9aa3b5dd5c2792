//! The undo and redo history of one explorer's scene, bounded in steps ([`UNDO_LIMIT`]) and in
//! bytes ([`UNDO_BYTES`]): at thousands of obstacles a scene is about 100 kB, and a thousand of
//! them would hold 100 MB per session. The oldest steps go first.

use std::collections::VecDeque;

use crate::scene::{ObstacleSpec, Scene, SegmentSpec};

/// Most undo steps kept.
pub const UNDO_LIMIT: usize = 1000;
/// Most bytes the undo and redo steps together may hold (8 MiB: about 80 steps at 4000
/// obstacles, the full [`UNDO_LIMIT`] below about 350).
pub const UNDO_BYTES: usize = 8 << 20;

/// Earlier scenes (undo, the newest last) and undone ones (redo).
#[derive(Debug, Clone, Default)]
pub struct History {
    undo: VecDeque<Scene>,
    redo: Vec<Scene>,
    bytes: usize,
}

/// About how many bytes `scene` holds.
pub fn scene_bytes(scene: &Scene) -> usize {
    std::mem::size_of::<Scene>()
        + scene.title.len()
        + scene.description.len()
        + scene.obstacles.len() * std::mem::size_of::<ObstacleSpec>()
        + scene.beam.segments.len() * std::mem::size_of::<SegmentSpec>()
}

impl History {
    /// Undo steps kept.
    pub fn undo_len(&self) -> usize {
        self.undo.len()
    }

    /// Redo steps kept.
    pub fn redo_len(&self) -> usize {
        self.redo.len()
    }

    /// Bytes the steps hold (see [`scene_bytes`]).
    pub fn bytes(&self) -> usize {
        self.bytes
    }

    /// Keeps `scene` (the one before a change) for undo; the redo steps are forgotten.
    pub fn remember(&mut self, scene: Scene) {
        for dropped in self.redo.drain(..) {
            self.bytes -= scene_bytes(&dropped);
        }
        self.push(true, scene);
    }

    /// The newest undo (`undo`) or redo step, taken out.
    pub fn pop(&mut self, undo: bool) -> Option<Scene> {
        let scene = if undo {
            self.undo.pop_back()
        } else {
            self.redo.pop()
        }?;
        self.bytes -= scene_bytes(&scene);
        Some(scene)
    }

    /// Keeps `scene` as the newest undo (`undo`) or redo step, the redo steps untouched;
    /// the oldest undo steps go when the limits are passed.
    pub fn push(&mut self, undo: bool, scene: Scene) {
        self.bytes += scene_bytes(&scene);
        if undo {
            self.undo.push_back(scene);
        } else {
            self.redo.push(scene);
        }
        while (self.undo.len() > UNDO_LIMIT || self.bytes > UNDO_BYTES) && !self.undo.is_empty() {
            if let Some(oldest) = self.undo.pop_front() {
                self.bytes -= scene_bytes(&oldest);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::preset;

    fn scene(obstacles: usize) -> Scene {
        let mut scene = Scene::from_toml(preset("benchmark-1").unwrap().text, "test").unwrap();
        scene.obstacles = vec![scene.obstacles[0]; obstacles];
        scene
    }

    #[test]
    fn the_history_is_bounded_in_steps_and_in_bytes_oldest_first() {
        let mut history = History::default();
        for _ in 0..UNDO_LIMIT + 10 {
            history.remember(scene(1));
        }
        assert_eq!(history.undo_len(), UNDO_LIMIT);
        let mut history = History::default();
        let big = scene(4000);
        for _ in 0..1000 {
            history.remember(big.clone());
        }
        assert!(history.bytes() <= UNDO_BYTES, "{}", history.bytes());
        let steps = UNDO_BYTES / scene_bytes(&big);
        assert_eq!(history.undo_len(), steps);
        // Undo and redo move steps between the two and keep the count of bytes.
        let before = history.bytes();
        let undone = history.pop(true).unwrap();
        history.push(false, undone);
        assert_eq!((history.undo_len(), history.redo_len()), (steps - 1, 1));
        assert_eq!(history.bytes(), before);
        history.remember(scene(1));
        assert_eq!(history.redo_len(), 0);
    }
}
