//! The house rules, checked on the source itself (read as Rust by `syn`, production code only:
//! `#[cfg(test)]` modules are left out):
//!
//! - no file in `src` over 600 lines, no function over 120; no file of the tests, the benches
//!   or the design notes (`tests`, `benches`, `docs`) over 600 lines either;
//! - the explorer's layers import only downwards — jobs < state < input < layout < view <
//!   update < runtime < `tui/mod.rs` — and no files of `src/tui` import each other in a
//!   circle (names taken through a `pub use` count as taken from the file that defines them);
//! - only the update layer changes the explorer's state: a function outside `tui/update` and
//!   `tui/runtime` (which hands the update its messages) never takes `&mut App` or
//!   `&mut Exploration`, and nothing outside `tui/update` assigns to a field of an `app`.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

use syn::spanned::Spanned;
use syn::visit::Visit;

const FILE_LIMIT: usize = 600;
const FUNCTION_LIMIT: usize = 120;
/// The explorer's layers, bottom up; `tui` is `src/tui/mod.rs` itself, above them all.
const LAYERS: [&str; 8] = [
    "jobs", "state", "input", "layout", "view", "update", "runtime", "tui",
];

/// A module path inside the crate, e.g. `["tui", "state", "app"]`.
type Module = Vec<String>;

/// One source file of the library.
struct Source {
    /// The path from the crate's root, e.g. `src/tui/state/app.rs`.
    path: String,
    module: Module,
    text: String,
    syntax: syn::File,
}

/// Every `.rs` file under `src` but the binary's `main.rs`.
fn sources() -> Vec<Source> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut files = Vec::new();
    collect(&root.join("src"), &mut files);
    files.sort();
    files
        .into_iter()
        .filter(|path| !path.ends_with("src/main.rs"))
        .map(|path| {
            let relative = path
                .strip_prefix(root)
                .unwrap()
                .to_string_lossy()
                .into_owned();
            let text = std::fs::read_to_string(&path).unwrap();
            let syntax = syn::parse_file(&text).unwrap_or_else(|e| panic!("{relative}: {e}"));
            Source {
                module: module_of(&relative),
                path: relative,
                text,
                syntax,
            }
        })
        .collect()
}

fn collect(dir: &Path, files: &mut Vec<PathBuf>) {
    for entry in std::fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        if path.is_dir() {
            collect(&path, files);
        } else if path.extension().is_some_and(|e| e == "rs") {
            files.push(path);
        }
    }
}

/// The module a file holds: `src/lib.rs` the crate, `src/a/mod.rs` and `src/a.rs` module `a`.
fn module_of(path: &str) -> Module {
    let inside = path.trim_start_matches("src/").trim_end_matches(".rs");
    let mut module: Module = inside.split('/').map(String::from).collect();
    if matches!(module.last().map(String::as_str), Some("mod" | "lib")) {
        module.pop();
    }
    module
}

/// Is this item compiled only for tests?
fn is_test_only(attrs: &[syn::Attribute]) -> bool {
    attrs.iter().any(|a| {
        a.path().is_ident("cfg")
            && a.parse_args::<syn::Meta>()
                .is_ok_and(|m| m.path().is_ident("test"))
    })
}

/// The line span of a function: from `fn` to its closing brace.
fn function_lines(fn_token: &syn::token::Fn, block: &syn::Block) -> usize {
    let start = fn_token.span.start().line;
    let end = block.brace_token.span.close().end().line;
    end - start + 1
}

/// Functions longer than the limit, with where they start.
#[derive(Default)]
struct LongFunctions(Vec<(String, usize, usize)>);

impl<'a> Visit<'a> for LongFunctions {
    fn visit_item_fn(&mut self, item: &'a syn::ItemFn) {
        let lines = function_lines(&item.sig.fn_token, &item.block);
        if lines > FUNCTION_LIMIT {
            let line = item.sig.fn_token.span.start().line;
            self.0.push((item.sig.ident.to_string(), line, lines));
        }
        syn::visit::visit_item_fn(self, item);
    }

    fn visit_impl_item_fn(&mut self, item: &'a syn::ImplItemFn) {
        let lines = function_lines(&item.sig.fn_token, &item.block);
        if lines > FUNCTION_LIMIT {
            let line = item.sig.fn_token.span.start().line;
            self.0.push((item.sig.ident.to_string(), line, lines));
        }
        syn::visit::visit_impl_item_fn(self, item);
    }
}

#[test]
fn no_file_over_600_lines_and_no_function_over_120() {
    let mut broken = Vec::new();
    for source in sources() {
        let lines = source.text.lines().count();
        if lines > FILE_LIMIT {
            broken.push(format!("{}: {lines} lines", source.path));
        }
        let mut long = LongFunctions::default();
        long.visit_file(&source.syntax);
        for (name, line, lines) in long.0 {
            broken.push(format!(
                "{}:{line}: fn {name} has {lines} lines",
                source.path
            ));
        }
    }
    assert!(broken.is_empty(), "too long:\n{}", broken.join("\n"));
}

/// Every file with one of `extensions` under `dir` (relative to the crate's root), its path
/// from the root.
fn files_under(dir: &str, extensions: &[&str]) -> Vec<PathBuf> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut files = Vec::new();
    let mut dirs = vec![root.join(dir)];
    while let Some(dir) = dirs.pop() {
        for entry in std::fs::read_dir(&dir).unwrap() {
            let path = entry.unwrap().path();
            if path.is_dir() {
                dirs.push(path);
            } else if path
                .extension()
                .is_some_and(|e| extensions.iter().any(|x| e == *x))
            {
                files.push(path.strip_prefix(root).unwrap().to_path_buf());
            }
        }
    }
    files.sort();
    files
}

#[test]
fn no_test_bench_or_design_note_over_600_lines() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let files = [
        files_under("tests", &["rs"]),
        files_under("benches", &["rs", "py"]),
        files_under("docs", &["md"]),
    ]
    .concat();
    // The walk found them: this test reads the files it is about.
    assert!(files.iter().any(|f| f.ends_with("docs/numerics.md")));
    assert!(
        files
            .iter()
            .any(|f| f.ends_with("tests/it/architecture.rs"))
    );
    let broken: Vec<String> = files
        .iter()
        .filter_map(|file| {
            let lines = std::fs::read_to_string(root.join(file))
                .unwrap()
                .lines()
                .count();
            (lines > FILE_LIMIT).then(|| format!("{}: {lines} lines", file.display()))
        })
        .collect();
    assert!(broken.is_empty(), "too long:\n{}", broken.join("\n"));
}

/// The paths a file names (in `use` items and in code), outside its test-only modules, each
/// as written: `crate::…`, `super::…`, `self::…` or anything else.
#[derive(Default)]
struct Paths {
    paths: Vec<Vec<String>>,
    /// Names a `pub use` makes public here, and the path each comes from.
    reexports: Vec<(String, Vec<String>)>,
    /// Nesting inside inline modules (their paths are relative to them: not followed).
    inline: usize,
}

impl Paths {
    fn use_tree(&mut self, prefix: &mut Vec<String>, tree: &syn::UseTree, public: bool) {
        match tree {
            syn::UseTree::Path(p) => {
                prefix.push(p.ident.to_string());
                self.use_tree(prefix, &p.tree, public);
                prefix.pop();
            }
            syn::UseTree::Name(n) => self.leaf(prefix, &n.ident.to_string(), None, public),
            syn::UseTree::Rename(r) => {
                let alias = r.rename.to_string();
                self.leaf(prefix, &r.ident.to_string(), Some(alias), public);
            }
            syn::UseTree::Glob(_) => self.paths.push(prefix.clone()),
            syn::UseTree::Group(g) => {
                for tree in &g.items {
                    self.use_tree(prefix, tree, public);
                }
            }
        }
    }

    fn leaf(&mut self, prefix: &[String], name: &str, alias: Option<String>, public: bool) {
        let mut path = prefix.to_vec();
        if name != "self" {
            path.push(name.to_string());
        }
        if public {
            let shown = alias.unwrap_or_else(|| path.last().cloned().unwrap_or_default());
            self.reexports.push((shown, path.clone()));
        }
        self.paths.push(path);
    }
}

impl<'a> Visit<'a> for Paths {
    fn visit_item_mod(&mut self, item: &'a syn::ItemMod) {
        if is_test_only(&item.attrs) {
            return;
        }
        self.inline += usize::from(item.content.is_some());
        syn::visit::visit_item_mod(self, item);
        self.inline -= usize::from(item.content.is_some());
    }

    fn visit_item_use(&mut self, item: &'a syn::ItemUse) {
        if self.inline == 0 {
            let public = matches!(item.vis, syn::Visibility::Public(_));
            self.use_tree(&mut Vec::new(), &item.tree, public);
        }
    }

    /// `pub(super)` and the like name no module to take anything from.
    fn visit_visibility(&mut self, _: &'a syn::Visibility) {}

    fn visit_path(&mut self, path: &'a syn::Path) {
        let first = path.segments.first().map(|s| s.ident.to_string());
        if self.inline == 0 && matches!(first.as_deref(), Some("crate" | "super" | "self")) {
            self.paths
                .push(path.segments.iter().map(|s| s.ident.to_string()).collect());
        }
        syn::visit::visit_path(self, path);
    }
}

/// The crate's modules and what their files name, to find which file a path leads to.
struct Crate {
    files: BTreeMap<Module, String>,
    paths: BTreeMap<Module, Paths>,
}

impl Crate {
    fn new(sources: &[Source]) -> Crate {
        let mut files = BTreeMap::new();
        let mut paths = BTreeMap::new();
        for source in sources {
            let mut seen = Paths::default();
            seen.visit_file(&source.syntax);
            files.insert(source.module.clone(), source.path.clone());
            paths.insert(source.module.clone(), seen);
        }
        Crate { files, paths }
    }

    /// The module (with a file) that `path`, written in `from`, leads to: the module it names,
    /// or the one defining the item it names (through `pub use` re-exports); `None` outside
    /// the crate.
    fn resolve(&self, from: &Module, path: &[String], depth: usize) -> Option<Module> {
        let (mut module, rest) = match path.first().map(String::as_str) {
            Some("crate") => (Vec::new(), &path[1..]),
            Some("self") => (from.clone(), &path[1..]),
            Some("super") => {
                let supers = path.iter().take_while(|s| *s == "super").count();
                let keep = from.len().checked_sub(supers)?;
                (from[..keep].to_vec(), &path[supers..])
            }
            // A name of this module (a child module, or an item in scope).
            Some(_) => (from.clone(), path),
            None => return None,
        };
        for segment in rest {
            let mut child = module.clone();
            child.push(segment.clone());
            if self.files.contains_key(&child) {
                module = child;
                continue;
            }
            // An item of `module`: defined there, or re-exported from elsewhere.
            let reexported = self.paths.get(&module).and_then(|p| {
                p.reexports
                    .iter()
                    .find(|(name, _)| name == segment)
                    .map(|(_, origin)| origin.clone())
            });
            return match reexported {
                Some(origin) if depth < 8 => self.resolve(&module, &origin, depth + 1),
                _ => Some(module),
            };
        }
        Some(module)
    }

    /// The files of `src/tui` each file of it takes names from.
    fn explorer_imports(&self) -> BTreeMap<Module, BTreeSet<Module>> {
        let mut imports = BTreeMap::new();
        for (module, paths) in &self.paths {
            if module.first().map(String::as_str) != Some("tui") {
                continue;
            }
            let targets: BTreeSet<Module> = paths
                .paths
                .iter()
                .filter_map(|path| self.resolve(module, path, 0))
                .filter(|target| target.first().map(String::as_str) == Some("tui"))
                .filter(|target| target != module && self.files.contains_key(target))
                .collect();
            imports.insert(module.clone(), targets);
        }
        imports
    }
}

/// The layer of a module of the explorer: its folder under `tui`, or `tui` for `tui/mod.rs`.
fn layer(module: &Module) -> usize {
    let name = module.get(1).map_or("tui", String::as_str);
    LAYERS
        .iter()
        .position(|l| *l == name)
        .unwrap_or_else(|| panic!("tui::{name} is no layer of {LAYERS:?}"))
}

#[test]
fn the_explorers_layers_import_only_downwards_and_without_circles() {
    let sources = sources();
    let krate = Crate::new(&sources);
    let imports = krate.explorer_imports();
    assert!(imports.len() > 40, "the explorer's files were not found");
    let file = |m: &Module| krate.files[m].clone();
    let mut upward = Vec::new();
    for (module, targets) in &imports {
        for target in targets {
            if layer(target) > layer(module) {
                upward.push(format!("{} -> {}", file(module), file(target)));
            }
        }
    }
    assert!(
        upward.is_empty(),
        "imports that run up:\n{}",
        upward.join("\n")
    );
    // Circles: a depth-first search that meets a file still on its path.
    let mut done = BTreeSet::new();
    let mut circles = Vec::new();
    for start in imports.keys() {
        let mut path = Vec::new();
        find_circle(start, &imports, &mut path, &mut done, &mut circles);
    }
    let circles: Vec<String> = circles
        .iter()
        .map(|c: &Vec<Module>| c.iter().map(file).collect::<Vec<_>>().join(" -> "))
        .collect();
    assert!(
        circles.is_empty(),
        "import circles:\n{}",
        circles.join("\n")
    );
}

fn find_circle(
    module: &Module,
    imports: &BTreeMap<Module, BTreeSet<Module>>,
    path: &mut Vec<Module>,
    done: &mut BTreeSet<Module>,
    circles: &mut Vec<Vec<Module>>,
) {
    if let Some(at) = path.iter().position(|m| m == module) {
        let mut circle = path[at..].to_vec();
        circle.push(module.clone());
        circles.push(circle);
        return;
    }
    if done.contains(module) {
        return;
    }
    path.push(module.clone());
    for target in imports.get(module).into_iter().flatten() {
        find_circle(target, imports, path, done, circles);
    }
    path.pop();
    done.insert(module.clone());
}

/// Functions that take the explorer's state mutably, and assignments to a field of `app`.
#[derive(Default)]
struct Writers {
    mutable_state: Vec<(String, usize)>,
    assignments: Vec<usize>,
}

impl Writers {
    fn signature(&mut self, sig: &syn::Signature) {
        for input in &sig.inputs {
            let syn::FnArg::Typed(arg) = input else {
                continue;
            };
            if let syn::Type::Reference(r) = arg.ty.as_ref()
                && r.mutability.is_some()
                && let syn::Type::Path(p) = r.elem.as_ref()
                && p.path
                    .segments
                    .last()
                    .is_some_and(|s| s.ident == "App" || s.ident == "Exploration")
            {
                let line = sig.fn_token.span.start().line;
                self.mutable_state.push((sig.ident.to_string(), line));
            }
        }
    }

    fn assigned(&mut self, target: &syn::Expr) {
        let mut root = target;
        loop {
            root = match root {
                syn::Expr::Field(f) => &f.base,
                syn::Expr::Index(i) => &i.expr,
                _ => break,
            };
        }
        let is_field = !matches!(target, syn::Expr::Path(_));
        if is_field
            && let syn::Expr::Path(p) = root
            && p.path.is_ident("app")
        {
            self.assignments.push(target.span().start().line);
        }
    }
}

impl<'a> Visit<'a> for Writers {
    fn visit_item_mod(&mut self, item: &'a syn::ItemMod) {
        if !is_test_only(&item.attrs) {
            syn::visit::visit_item_mod(self, item);
        }
    }

    fn visit_signature(&mut self, sig: &'a syn::Signature) {
        self.signature(sig);
        syn::visit::visit_signature(self, sig);
    }

    fn visit_expr_assign(&mut self, e: &'a syn::ExprAssign) {
        self.assigned(&e.left);
        syn::visit::visit_expr_assign(self, e);
    }

    fn visit_expr_binary(&mut self, e: &'a syn::ExprBinary) {
        use syn::BinOp::*;
        if matches!(
            e.op,
            AddAssign(_) | SubAssign(_) | MulAssign(_) | DivAssign(_) | RemAssign(_)
        ) {
            self.assigned(&e.left);
        }
        syn::visit::visit_expr_binary(self, e);
    }
}

#[test]
fn only_the_update_layer_changes_the_explorers_state() {
    let mut broken = Vec::new();
    for source in sources() {
        let mut writers = Writers::default();
        writers.visit_file(&source.syntax);
        let in_update = source.path.starts_with("src/tui/update/");
        let in_runtime = source.path.starts_with("src/tui/runtime/");
        if !(in_update || in_runtime) {
            for (name, line) in writers.mutable_state {
                broken.push(format!(
                    "{}:{line}: fn {name} takes the state mutably",
                    source.path
                ));
            }
        }
        if !in_update {
            for line in writers.assignments {
                broken.push(format!("{}:{line}: assigns to the state", source.path));
            }
        }
    }
    assert!(broken.is_empty(), "{}", broken.join("\n"));
}
