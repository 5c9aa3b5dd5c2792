//! What a key means: the explorer's actions, as the keymap's tables bind them to keys in each
//! mode and `tui::update` applies them.

use super::super::keys::Key;

/// What the user asked for.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Action {
    /// Previous parameter row, or previous entry of a list.
    SelectPrevious,
    /// Next parameter row, or next entry of a list.
    SelectNext,
    /// The first row or entry (`g`, Home).
    SelectFirst,
    /// The last row or entry (`G`, End).
    SelectLast,
    /// A page up (PgUp).
    PageUp,
    /// A page down (PgDn).
    PageDown,
    /// The focused panel fills the screen, or back.
    ToggleZoom,
    /// Change the selected value one step down; `coarse` for a coarse step.
    Decrease {
        coarse: bool,
    },
    /// One step up.
    Increase {
        coarse: bool,
    },
    /// Type an exact value for the selected row.
    EditValue,
    AddObstacle,
    DeleteObstacle,
    NextMethod,
    PickPreset,
    Save,
    /// Back to the scene as loaded.
    Reset,
    /// Deflection, bending moment, shear.
    NextDiagram,
    /// The next panel when one is shown at a time.
    NextPanel,
    /// The next set of panels: the scene's own, the method at work, Figure 5, the matrices.
    NextPanelSet,
    /// The iterations panel's selected iterate: one back (−1) or on (+1).
    StepIterate(i8),
    ToggleTimings,
    /// The deflection panel: u and the reference u_ref, or the difference u − u_ref.
    ToggleDifference,
    /// The next colour palette (dark, light, high contrast).
    CycleTheme,
    /// Write the focused panel as an SVG figure.
    ExportFigure,
    /// The next marker set of the charts' curves (Braille, half blocks, … ASCII).
    CycleMarkers,
    ShowHelp,
    /// Every warning of the solution shown, in full.
    ShowWarnings,
    /// Take back the last change of the scene.
    Undo,
    /// Do again what was undone.
    Redo,
    Quit,
    /// Ctrl-C: quit from anywhere.
    Interrupt,
    /// Ctrl-Z: suspend (the shell's `fg` resumes).
    Suspend,
    /// A character typed into a prompt.
    Type(char),
    /// Delete the character before a prompt's cursor.
    DeleteChar,
    /// Move a prompt's cursor one character left.
    CursorLeft,
    /// One character right.
    CursorRight,
    /// To the start of the prompt.
    CursorHome,
    /// To its end.
    CursorEnd,
    /// Erase the prompt's text before the cursor (Ctrl-U).
    EraseToStart,
    /// Accept a prompt, a list entry or a question.
    Confirm,
    /// Leave a prompt, an overlay or a question without doing anything.
    Cancel,
    /// A key that means nothing in normal mode (its name goes into the message).
    Unbound(Key),
    /// Text pasted where no prompt takes it: ignored, never run as commands.
    PasteIgnored,
    /// Follow mode: leave the presenter, exploring on from the current state.
    Fork,
    /// Follow mode: follow the presenter again.
    Rejoin,
    /// A lecturer's explorer: show how students join the class.
    ShowJoin,
    /// The presenter's list of students (`S`).
    ShowStudents,
    /// Every student follows the presenter again (a fork with unsaved work is asked).
    BringEveryoneBack,
    /// Type a line for every student.
    WriteBroadcast,
    /// The lesson's next step (Space, `n`).
    NextStep,
    /// The lesson's step before (Backspace, `N`).
    PreviousStep,
}
