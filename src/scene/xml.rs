//! Reading scene XML into an owned element tree: dialect detection, Mitsuba
//! `<include>`, `<default>` and `$name` substitution, with the file and line of every
//! element kept for messages.
//!
//! The dialect loaders (`mitsuba`, `nori`) walk the [`Element`] tree this produces; they
//! never see roxmltree.

use std::cell::RefCell;
use std::path::{Path, PathBuf};
use std::rc::Rc;

use super::Error;

/// Which scene format a file is written in.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Dialect {
    /// Mitsuba 3: `<scene version="3.x.y">`, `<sensor>`, `<shape>`.
    Mitsuba,
    /// Nori: `<scene>` without a version, `<camera>`, `<mesh>`.
    Nori,
}

/// Nested `<include>` deeper than this is an error (Mitsuba's own limit is 15).
const MAX_INCLUDE_DEPTH: usize = 32;

/// One XML element after includes and substitutions, with where it was written.
#[derive(Debug, Clone)]
pub struct Element {
    pub tag: String,
    pub attrs: Vec<(String, String)>,
    pub children: Vec<Element>,
    /// The file this element was read from (an included file, for included elements).
    pub file: Rc<PathBuf>,
    pub line: u32,
    /// Where relative file names are searched besides the element's own folder: the
    /// scene's `<path>` folders and the folder of the scene file `load` was given.
    pub search: Rc<SearchPath>,
}

/// Mitsuba's file resolver for one scene: the folder of the main scene file, and the
/// folders its `<path value="..."/>` tags add (each relative to the file holding the
/// tag, as Mitsuba's parser makes them). Later `<path>`s are searched first, as
/// Mitsuba prepends them. File names are resolved after the whole scene is read (as
/// Mitsuba's plugins resolve them when they are built), so a `<path>` of the main
/// file applies to every file the scene names; an `<include>` sees the `<path>`s above
/// it. A `<path>` in an included file applies to the includes of that file only.
#[derive(Debug)]
pub struct SearchPath {
    /// The main scene file's folder.
    pub base: PathBuf,
    /// `<path>` folders, in document order.
    paths: RefCell<Vec<PathBuf>>,
}

impl SearchPath {
    fn new(base: PathBuf) -> SearchPath {
        SearchPath {
            base,
            paths: RefCell::new(Vec::new()),
        }
    }

    /// The `<path>` folders, most recent first.
    pub fn paths(&self) -> Vec<PathBuf> {
        self.paths.borrow().iter().rev().cloned().collect()
    }

    /// Resolves a file name a plugin names ([`Element::resolve`]), as Mitsuba 3.9.1
    /// does when it builds the plugin after the whole scene is parsed: in the main
    /// file's `<path>` folders (most recent first), then the main scene's folder. Not
    /// in the folder of an included file that names it, nor in `<path>`s written in
    /// included files: their resolver scope ends with the included file (checked with
    /// `mi.load_file`).
    pub fn resolve(&self, name: &str) -> Result<PathBuf, String> {
        self.resolve_in(&[], name)
    }

    /// Resolves a name in the folders `first`, then as [`SearchPath::resolve`].
    fn resolve_in(&self, first: &[PathBuf], name: &str) -> Result<PathBuf, String> {
        let mut tried: Vec<PathBuf> = Vec::new();
        let dirs = if Path::new(name).is_absolute() {
            vec![PathBuf::new()]
        } else {
            let mut dirs = first.to_vec();
            dirs.extend(self.paths());
            dirs.push(self.base.clone());
            dirs
        };
        for dir in dirs {
            let candidate = dir.join(name);
            if tried.contains(&candidate) {
                continue;
            }
            if candidate.is_file() {
                return Ok(candidate);
            }
            tried.push(candidate);
        }
        let mut tried = tried.iter().map(|p| format!("'{}'", p.display()));
        let first = tried.next().unwrap_or_default();
        let rest: Vec<String> = tried.collect();
        if rest.is_empty() {
            Err(first)
        } else {
            Err(format!("{first} (nor {})", rest.join(", ")))
        }
    }
}

impl Element {
    /// The value of attribute `name`, if present.
    pub fn attr(&self, name: &str) -> Option<&str> {
        self.attrs
            .iter()
            .find(|(k, _)| k == name)
            .map(|(_, v)| v.as_str())
    }

    /// The value of attribute `name`, or an error naming the element.
    pub fn require(&self, name: &str) -> Result<&str, Error> {
        self.attr(name)
            .ok_or_else(|| self.err(format!("<{}> needs a '{}' attribute", self.tag, name)))
    }

    /// Errors on any attribute not in `allowed`.
    pub fn check_attrs(&self, allowed: &[&str]) -> Result<(), Error> {
        for (k, _) in &self.attrs {
            if !allowed.contains(&k.as_str()) {
                return Err(self.err(format!("unexpected attribute '{}' in <{}>", k, self.tag)));
            }
        }
        Ok(())
    }

    /// An error at this element's line.
    pub fn err(&self, message: impl Into<String>) -> Error {
        Error::at(self.file.as_path(), self.line, message)
    }

    /// The folder relative paths inside this element resolve against first.
    pub fn dir(&self) -> &Path {
        self.file.parent().unwrap_or(Path::new(""))
    }

    /// Resolves a file name written in this element as Mitsuba's file resolver does
    /// for a plugin ([`SearchPath::resolve`]): an absolute name as is; a relative one in
    /// the main file's `<path>` folders (most recent first), then the main scene's
    /// folder. On failure, the paths tried.
    pub fn resolve(&self, name: &str) -> Result<PathBuf, String> {
        self.search.resolve(name)
    }
}

/// A scene file read into an element tree.
#[derive(Debug)]
pub struct Document {
    pub dialect: Dialect,
    /// The root `<scene>`, its children with includes spliced in.
    pub root: Element,
}

/// Reads `path`, detects its dialect and expands it. `defines` override Mitsuba
/// `<default>`s; they are an error for a Nori scene, which has no defaults.
pub fn read(path: &Path, defines: &[(String, String)]) -> Result<Document, Error> {
    let text = read_text(path)?;
    let doc = parse(path, &text)?;
    let root = doc.xml.root_element();
    let dialect = detect(path, &doc, root)?;
    if dialect == Dialect::Nori && !defines.is_empty() {
        return Err(Error::file(
            path,
            format!(
                "-D {}=... has no effect: this is a Nori scene, and only Mitsuba 3 scenes have <default> parameters",
                defines[0].0
            ),
        ));
    }
    let file = Rc::new(path.to_path_buf());
    let search = Rc::new(SearchPath::new(
        path.parent().unwrap_or(Path::new("")).to_path_buf(),
    ));
    let mut expander = Expander {
        dialect,
        search: search.clone(),
        params: defines.to_vec(),
        stack: vec![canonical(path)],
        scoped: Vec::new(),
    };
    let line = line_of(&doc, root);
    let mut attrs = Vec::new();
    for a in root.attributes() {
        attrs.push((a.name().to_string(), a.value().to_string()));
    }
    let children = expander.children(&doc, root, &file)?;
    Ok(Document {
        dialect,
        root: Element {
            tag: root.tag_name().name().to_string(),
            attrs,
            children,
            file,
            line,
            search,
        },
    })
}

fn read_text(path: &Path) -> Result<String, Error> {
    let bytes = std::fs::read(path).map_err(|e| {
        Error::file(
            path,
            if e.kind() == std::io::ErrorKind::NotFound {
                "file not found".to_string()
            } else {
                format!("cannot read: {e}")
            },
        )
    })?;
    String::from_utf8(bytes).map_err(|e| {
        Error::file(
            path,
            format!(
                "not UTF-8 text (bad byte at offset {})",
                e.utf8_error().valid_up_to()
            ),
        )
    })
}

/// A parsed document and where its newlines are, for the line of each element by
/// binary search: roxmltree's `text_pos_at` counts the newlines before a position on
/// every call, which made loading quadratic in the elements (10,000 shapes: 50 s).
struct Doc<'a> {
    xml: roxmltree::Document<'a>,
    newlines: Vec<usize>,
}

fn parse<'a>(path: &Path, text: &'a str) -> Result<Doc<'a>, Error> {
    let xml = roxmltree::Document::parse(text)
        .map_err(|e| Error::at(path, e.pos().row, format!("malformed XML: {e}")))?;
    let newlines = memchr::memchr_iter(b'\n', text.as_bytes()).collect();
    Ok(Doc { xml, newlines })
}

/// The 1-based line `node` starts on (as roxmltree's `text_pos_at` counts it).
fn line_of(doc: &Doc, node: roxmltree::Node) -> u32 {
    let start = node.range().start;
    1 + doc.newlines.partition_point(|&p| p < start) as u32
}

fn canonical(path: &Path) -> PathBuf {
    std::fs::canonicalize(path).unwrap_or_else(|_| path.to_path_buf())
}

/// Tags only a Mitsuba 3 scene uses at the top level, and tags only Nori uses.
const MITSUBA_TAGS: &[&str] = &[
    "sensor", "shape", "default", "include", "film", "texture", "alias", "path",
];
const NORI_TAGS: &[&str] = &["camera", "mesh"];

fn detect(path: &Path, doc: &Doc, root: roxmltree::Node) -> Result<Dialect, Error> {
    let line = line_of(doc, root);
    let tag = root.tag_name().name();
    if tag != "scene" {
        return Err(Error::at(
            path,
            line,
            format!("the root element must be <scene>, found <{tag}>"),
        ));
    }
    if let Some(version) = root.attribute("version") {
        let parts: Vec<Option<u32>> = version.split('.').map(|p| p.trim().parse().ok()).collect();
        if parts.len() != 3 || parts.iter().any(|p| p.is_none()) {
            return Err(Error::at(
                path,
                line,
                format!("could not parse version \"{version}\" (expected three numbers, e.g. \"3.0.0\")"),
            ));
        }
        if parts[0] < Some(2) {
            return Err(Error::at(
                path,
                line,
                format!("Mitsuba {version} scenes (camelCase parameter names) are not supported; convert the scene to version 3"),
            ));
        }
        return Ok(Dialect::Mitsuba);
    }
    let tags: Vec<&str> = root
        .children()
        .filter(|n| n.is_element())
        .map(|n| n.tag_name().name())
        .collect();
    if let Some(t) = tags.iter().find(|t| MITSUBA_TAGS.contains(t)) {
        return Err(Error::at(
            path,
            line,
            format!("<scene> has no version attribute but uses the Mitsuba tag <{t}>; Mitsuba 3 scenes need <scene version=\"3.0.0\">"),
        ));
    }
    if tags.iter().any(|t| NORI_TAGS.contains(t)) {
        return Ok(Dialect::Nori);
    }
    Err(Error::at(
        path,
        line,
        "cannot tell the scene format: <scene> has no version attribute (Mitsuba 3) and no <camera> or <mesh> (Nori)",
    ))
}

struct Expander {
    dialect: Dialect,
    search: Rc<SearchPath>,
    /// `$name` substitutions: `-D` defines first, then `<default>`s in document order.
    params: Vec<(String, String)>,
    /// Canonical paths of the files being read, outermost first (include cycle guard).
    stack: Vec<PathBuf>,
    /// The `<path>` folders of each included file being read, outermost first: they
    /// apply to the includes in that file only (Mitsuba's resolver scope).
    scoped: Vec<Vec<PathBuf>>,
}

impl Expander {
    fn children(
        &mut self,
        doc: &Doc,
        node: roxmltree::Node,
        file: &Rc<PathBuf>,
    ) -> Result<Vec<Element>, Error> {
        let mut out = Vec::new();
        for child in node.children() {
            if child.is_text() {
                if child.text().is_some_and(|t| !t.trim().is_empty()) {
                    return Err(Error::at(
                        file.as_path(),
                        line_of(doc, child),
                        format!("unexpected text inside <{}>", node.tag_name().name()),
                    ));
                }
                continue;
            }
            if !child.is_element() {
                continue; // comments, processing instructions
            }
            let line = line_of(doc, child);
            let tag = child.tag_name().name().to_string();
            let mut attrs = Vec::new();
            for a in child.attributes() {
                let value = self.substitute(a.value(), file, line)?;
                attrs.push((a.name().to_string(), value));
            }
            let mut el = Element {
                tag,
                attrs,
                children: Vec::new(),
                file: file.clone(),
                line,
                search: self.search.clone(),
            };
            if self.dialect == Dialect::Mitsuba && el.tag == "default" {
                el.check_attrs(&["name", "value"])?;
                let name = el.require("name")?.to_string();
                let value = el.require("value")?.to_string();
                if name.is_empty() {
                    return Err(el.err("<default> needs a non-empty name"));
                }
                if !self.params.iter().any(|(k, _)| *k == name) {
                    self.params.push((name, value));
                }
                continue;
            }
            if self.dialect == Dialect::Mitsuba && el.tag == "path" {
                self.path(&el)?;
                continue;
            }
            if self.dialect == Dialect::Mitsuba && el.tag == "include" {
                out.extend(self.include(&el)?);
                continue;
            }
            el.children = self.children(doc, child, file)?;
            out.push(el);
        }
        Ok(out)
    }

    /// `<path value="DIR"/>`: adds DIR (relative to the file holding the tag) to the
    /// folders file names are searched in; a folder that does not exist is an error,
    /// as in Mitsuba.
    fn path(&mut self, el: &Element) -> Result<(), Error> {
        el.check_attrs(&["value"])?;
        let value = el.require("value")?;
        let dir = el.dir().join(value);
        if !dir.is_dir() {
            return Err(el.err(format!("<path>: folder '{}' not found", dir.display())));
        }
        match self.scoped.last_mut() {
            Some(scope) => scope.push(dir),
            None => self.search.paths.borrow_mut().push(dir),
        }
        Ok(())
    }

    fn include(&mut self, el: &Element) -> Result<Vec<Element>, Error> {
        el.check_attrs(&["filename"])?;
        let name = el.require("filename")?;
        // Parsing, Mitsuba resolves an include in the `<path>`s of the files being read
        // (most recent first), the including file's folder and the main folder.
        let mut first: Vec<PathBuf> = self.scoped.iter().flatten().rev().cloned().collect();
        first.extend(self.search.paths());
        first.push(el.dir().to_path_buf());
        let path = self
            .search
            .resolve_in(&first, name)
            .map_err(|tried| el.err(format!("included file {tried} not found")))?;
        let canon = canonical(&path);
        if self.stack.contains(&canon) {
            return Err(el.err(format!(
                "include cycle: '{}' is already being read",
                path.display()
            )));
        }
        if self.stack.len() > MAX_INCLUDE_DEPTH {
            return Err(el.err(format!(
                "includes nested deeper than {MAX_INCLUDE_DEPTH} levels"
            )));
        }
        let text = read_text(&path)?;
        let doc = parse(&path, &text)?;
        let root = doc.xml.root_element();
        let file = Rc::new(path);
        self.stack.push(canon);
        self.scoped.push(Vec::new());
        let result = if root.tag_name().name() == "scene" {
            self.children(&doc, root, &file)
        } else {
            // A file holding a single object: include that object.
            let line = line_of(&doc, root);
            let mut attrs = Vec::new();
            for a in root.attributes() {
                attrs.push((
                    a.name().to_string(),
                    self.substitute(a.value(), &file, line)?,
                ));
            }
            let children = self.children(&doc, root, &file)?;
            Ok(vec![Element {
                tag: root.tag_name().name().to_string(),
                attrs,
                children,
                file: file.clone(),
                line,
                search: self.search.clone(),
            }])
        };
        self.stack.pop();
        self.scoped.pop();
        result
    }

    /// Mitsuba's `$name` substitution: longest names first; any `$` left is an error.
    fn substitute(&self, value: &str, file: &Rc<PathBuf>, line: u32) -> Result<String, Error> {
        if self.dialect != Dialect::Mitsuba || !value.contains('$') {
            return Ok(value.to_string());
        }
        let mut params: Vec<&(String, String)> = self.params.iter().collect();
        params.sort_by_key(|(k, _)| std::cmp::Reverse(k.len()));
        let mut s = value.to_string();
        for (k, v) in params {
            s = s.replace(&format!("${k}"), v);
        }
        if s.contains('$') {
            return Err(Error::at(
                file.as_path(),
                line,
                format!("undefined parameter in \"{value}\" (no <default> or -D gives it a value)"),
            ));
        }
        Ok(s)
    }
}

/// Splits a list of numbers written with commas and/or whitespace.
pub fn tokens(s: &str) -> impl Iterator<Item = &str> {
    s.split(|c: char| c == ',' || c.is_whitespace())
        .filter(|t| !t.is_empty())
}

/// Parses a finite number; `None` for anything else (including "nan" and "inf").
pub fn parse_number(s: &str) -> Option<f64> {
    s.trim().parse::<f64>().ok().filter(|v| v.is_finite())
}

/// Parses a list of finite numbers written with commas and/or whitespace.
pub fn parse_numbers(s: &str) -> Option<Vec<f64>> {
    tokens(s).map(parse_number).collect()
}

#[cfg(test)]
mod tests {
    use crate::scene::testutil::load;

    const TRI: &str = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
    const SPHERE: &str = r#"<scene version="3.0.0"><shape type="sphere"/></scene>"#;

    fn main(body: &str) -> String {
        format!(r#"<scene version="3.0.0"><sensor type="perspective"/>{body}</scene>"#)
    }

    // Each case as Mitsuba 3.9.1's `mi.load_file` resolves it.

    #[test]
    fn an_included_files_path_serves_its_own_includes_only() {
        let frag =
            r#"<scene version="3.0.0"><path value="assets"/><include filename="b.xml"/></scene>"#;
        let files = |body: &str| {
            load(
                &[
                    ("main.xml", &main(body)),
                    ("sub/frag.xml", frag),
                    ("sub/assets/b.xml", SPHERE),
                    ("sub/assets/c.xml", SPHERE),
                ],
                &[],
            )
        };
        let s = files(r#"<include filename="sub/frag.xml"/>"#).unwrap();
        assert_eq!(s.quadrics.len(), 1);
        let e = files(r#"<include filename="sub/frag.xml"/><include filename="c.xml"/>"#)
            .unwrap_err()
            .to_string();
        assert!(e.contains("main.xml:1") && e.contains("c.xml"), "{e}");
    }

    #[test]
    fn a_plugins_file_is_found_by_the_main_files_paths_not_an_included_ones() {
        // A mesh beside the included file naming it, or in a <path> of that file, is
        // not found (Mitsuba builds the plugin after the included file's scope ended);
        // in a <path> of the main file, it is, even one written after the include.
        let shape = r#"<scene version="3.0.0"><shape type="obj"><string name="filename" value="tri.obj"/></shape></scene>"#;
        let with_path = r#"<scene version="3.0.0"><path value="assets"/><shape type="obj"><string name="filename" value="tri.obj"/></shape></scene>"#;
        for (frag, mesh) in [(shape, "sub/tri.obj"), (with_path, "sub/assets/tri.obj")] {
            let e = load(
                &[
                    ("main.xml", &main(r#"<include filename="sub/frag.xml"/>"#)),
                    ("sub/frag.xml", frag),
                    (mesh, TRI),
                ],
                &[],
            )
            .unwrap_err()
            .to_string();
            assert!(e.contains("frag.xml") && e.contains("tri.obj"), "{e}");
        }
        let s = load(
            &[
                (
                    "main.xml",
                    &main(r#"<include filename="sub/frag.xml"/><path value="sub/assets"/>"#),
                ),
                ("sub/frag.xml", shape),
                ("sub/assets/tri.obj", TRI),
            ],
            &[],
        )
        .unwrap();
        assert_eq!(s.meshes.len(), 1);
    }
}
