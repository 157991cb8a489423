//! Errors: user input problems (exit 1 in the CLI) kept apart from internal ones ("please report").
//!
//! Every input error names the file, the element id where there is one, the problem, and a hint
//! where one helps, so that the CLI can print it as one line.

use std::fmt;

/// The result type of crmorph.
pub type Result<T, E = Error> = std::result::Result<T, E>;

/// Everything that can go wrong in crmorph.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum Error {
    /// The input is unusable: a bad file, bad control geometry, or a morph that cannot be made
    /// from it. The fields say where and why.
    #[error("{0}")]
    Input(InputError),
    /// A bug in crmorph, not in the input.
    #[error("internal error: {0} (please report this with the input files)")]
    Internal(String),
}

/// A problem with the user's input, located as precisely as the stage that found it can.
#[derive(Debug, Clone, PartialEq)]
pub struct InputError {
    /// The file the problem is in (or the pair of files, for problems between them).
    pub file: String,
    /// The element id concerned (`boundary`, `feature-eye`, …), if any.
    pub element: Option<String>,
    /// What is wrong, in a short phrase without a trailing period.
    pub problem: String,
    /// How to fix it, if there is an obvious way.
    pub hint: Option<String>,
    /// Which of the two drawings the problem is in, when it was found by a stage that knows no
    /// file names (the triangulation of one side, the mapping, the interpolation): `file` then
    /// holds a placeholder (`<source>`, …) until [`Error::with_files`] names the files.
    /// `None` once named, or when `file` was known from the start.
    pub drawings: Option<Drawings>,
    /// Every control curve the problem concerns, by id, the element first (two features that
    /// cross, the curves a failed mapping folds near). Not printed: it is for code that
    /// decides on the problem, as automatic mode does when it gives up a feature, instead of
    /// searching the message for ids.
    /// (A boxed slice, not a `Vec`: errors travel in every `Result`, so they stay small.)
    pub curves: Box<[String]>,
    /// What kind of problem it is, for code that decides on it ([`ProblemKind`]).
    pub kind: ProblemKind,
}

/// The kind of an input problem, so that code deciding on a failure (automatic mode giving up
/// a feature, a library user's own retry) reads a value, not the message.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[non_exhaustive]
pub enum ProblemKind {
    /// Anything else: a file that cannot be read, a limit, a bad option.
    #[default]
    Other,
    /// The named element is unusable in itself: a control curve that crosses itself, is too
    /// short or open where it must be closed, a skeleton bone of zero length, an artwork
    /// element that cannot be drawn (every error made with [`Error::at`] until told otherwise).
    Element,
    /// Control curves cross or touch each other or the boundary (§3: features must lie inside
    /// the boundary, apart): [`InputError::curves`] holds the element and the curve it meets.
    Crossing,
    /// No flip-free mapping from one drawing to the other (§5, the paper's Fig. 16): the mesh
    /// folds near the curves in [`InputError::curves`].
    NoFlipFreeMapping,
}

/// Which of a morph's two drawings an input problem is in, for stages that work on geometry
/// alone and know no file names; [`Error::with_files`] names them.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Drawings {
    /// The source drawing.
    Source,
    /// The target drawing.
    Target,
    /// Both, as one problem each has (`a.svg and b.svg`).
    Both,
    /// The pair, for a problem between them (`a.svg → b.svg`: no mapping from one to the
    /// other).
    Pair,
}

impl Drawings {
    /// What the file reads as until it is named: `<source>`, `<target>`, `<source> and
    /// <target>`, `<source> → <target>`.
    pub fn placeholder(self) -> &'static str {
        match self {
            Drawings::Source => "<source>",
            Drawings::Target => "<target>",
            Drawings::Both => "<source> and <target>",
            Drawings::Pair => "<source> → <target>",
        }
    }

    /// The file name(s), given the source's and the target's.
    pub fn name(self, source: &str, target: &str) -> String {
        match self {
            Drawings::Source => source.to_string(),
            Drawings::Target => target.to_string(),
            Drawings::Both => format!("{source} and {target}"),
            Drawings::Pair => format!("{source} → {target}"),
        }
    }
}

/// Where an input problem is: a file by name, or one of the two drawings of a morph
/// ([`Drawings`]) not yet named.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Where {
    /// A file (or any place) by name.
    File(String),
    /// One of the drawings, named later.
    Drawings(Drawings),
}

impl From<&str> for Where {
    fn from(s: &str) -> Self {
        Where::File(s.to_string())
    }
}

impl From<String> for Where {
    fn from(s: String) -> Self {
        Where::File(s)
    }
}

impl From<&String> for Where {
    fn from(s: &String) -> Self {
        Where::File(s.clone())
    }
}

impl From<Drawings> for Where {
    fn from(d: Drawings) -> Self {
        Where::Drawings(d)
    }
}

impl Where {
    /// The file text and the unnamed drawings, as an [`InputError`] holds them.
    fn split(self) -> (String, Option<Drawings>) {
        match self {
            Where::File(f) => (f, None),
            Where::Drawings(d) => (d.placeholder().to_string(), Some(d)),
        }
    }
}

/// `s` safe to print on a terminal: control characters (and the other invisible formatting
/// characters a hostile file may put in an id) as `\u{…}` escapes, at most 200 characters.
pub fn printable(s: &str) -> String {
    escape(s, 200)
}

/// A message safe to print as one line on a terminal: control characters escaped as in
/// [`printable`], never shortened. Escaping twice changes nothing.
pub fn printable_line(s: &str) -> String {
    escape(s, usize::MAX)
}

/// A path as a file name for messages: lossy UTF-8, with control characters escaped as in
/// [`printable`] (but never shortened).
pub fn printable_path(path: &std::path::Path) -> String {
    escape(&path.to_string_lossy(), usize::MAX)
}

fn escape(s: &str, max_chars: usize) -> String {
    let mut out = String::with_capacity(s.len());
    for (k, c) in s.chars().enumerate() {
        if k == max_chars {
            out.push('…');
            break;
        }
        if c.is_control()
            || matches!(c, '\u{200b}'..='\u{200f}' | '\u{202a}'..='\u{202e}' | '\u{2066}'..='\u{2069}')
        {
            out.push_str(&format!("\\u{{{:x}}}", c as u32));
        } else {
            out.push(c);
        }
    }
    out
}

impl fmt::Display for InputError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        // Every part may quote the file (ids, paths): escaped, so that a hostile id cannot
        // drive the terminal or break the line.
        write!(f, "{}", printable_line(&self.file))?;
        if let Some(el) = &self.element {
            write!(f, ": element '{}'", printable(el))?;
        }
        write!(f, ": {}", printable_line(&self.problem))?;
        if let Some(h) = &self.hint {
            write!(f, " (hint: {})", printable_line(h))?;
        }
        Ok(())
    }
}

impl Error {
    /// An input error in `file` (a name, or one of the [`Drawings`]) with no particular
    /// element, of kind [`ProblemKind::Other`].
    pub fn input(file: impl Into<Where>, problem: impl Into<String>) -> Self {
        let (file, drawings) = file.into().split();
        Error::Input(InputError {
            file,
            drawings,
            element: None,
            problem: problem.into(),
            hint: None,
            curves: Box::default(),
            kind: ProblemKind::Other,
        })
    }

    /// An input error in `file` at the element with id `element`, of kind
    /// [`ProblemKind::Element`] (change it with [`Error::of_kind`]).
    pub fn at(
        file: impl Into<Where>,
        element: impl Into<String>,
        problem: impl Into<String>,
    ) -> Self {
        let element: String = element.into();
        let (file, drawings) = file.into().split();
        Error::Input(InputError {
            file,
            drawings,
            curves: Box::new([element.clone()]),
            element: Some(element),
            problem: problem.into(),
            hint: None,
            kind: ProblemKind::Element,
        })
    }

    /// Adds a hint to an input error (no effect on internal errors).
    pub fn with_hint(mut self, hint: impl Into<String>) -> Self {
        if let Error::Input(e) = &mut self {
            e.hint = Some(hint.into());
        }
        self
    }

    /// Adds control curves (by id) that an input error concerns ([`InputError::curves`]; no
    /// effect on internal errors).
    pub fn concerning<S: Into<String>>(mut self, ids: impl IntoIterator<Item = S>) -> Self {
        if let Error::Input(e) = &mut self {
            let mut curves = std::mem::take(&mut e.curves).into_vec();
            for id in ids {
                let id = id.into();
                if !curves.contains(&id) {
                    curves.push(id);
                }
            }
            e.curves = curves.into_boxed_slice();
        }
        self
    }

    /// Sets the kind of an input error ([`ProblemKind`]; no effect on internal errors).
    pub fn of_kind(mut self, kind: ProblemKind) -> Self {
        if let Error::Input(e) = &mut self {
            e.kind = kind;
        }
        self
    }

    /// The kind of an input error ([`InputError::kind`]); `None` for internal errors.
    pub fn kind(&self) -> Option<ProblemKind> {
        match self {
            Error::Input(e) => Some(e.kind),
            Error::Internal(_) => None,
        }
    }

    /// The control curves an input error concerns ([`InputError::curves`]); none for internal
    /// errors.
    pub fn curves(&self) -> &[String] {
        match self {
            Error::Input(e) => &e.curves,
            Error::Internal(_) => &[],
        }
    }

    /// Replaces the file of an input error (a name, or one of the [`Drawings`]).
    pub fn in_file(mut self, file: impl Into<Where>) -> Self {
        if let Error::Input(e) = &mut self {
            (e.file, e.drawings) = file.into().split();
        }
        self
    }

    /// Names the drawings of an input error found by a stage that knew no file names
    /// ([`InputError::drawings`]), given the source's and the target's; an error with its
    /// file known is unchanged.
    pub fn with_files(mut self, source: &str, target: &str) -> Self {
        if let Error::Input(e) = &mut self {
            if let Some(d) = e.drawings.take() {
                e.file = d.name(source, target);
            }
        }
        self
    }

    /// An internal error: a broken invariant of crmorph itself.
    pub fn internal(msg: impl Into<String>) -> Self {
        Error::Internal(msg.into())
    }

    /// True for input errors (the CLI exits with status 1 for these).
    pub fn is_input(&self) -> bool {
        matches!(self, Error::Input(_))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn input_error_is_one_line_with_file_element_and_hint() {
        let e =
            Error::at("a.svg", "boundary", "is not closed").with_hint("close the path with 'z'");
        let s = e.to_string();
        assert_eq!(
            s,
            "a.svg: element 'boundary': is not closed (hint: close the path with 'z')"
        );
        assert!(!s.contains('\n'));
        assert!(e.is_input());
        assert!(!Error::internal("x").is_input());
        let odd = Error::at("a.svg", "bad\u{1b}[31mid\n", "x").to_string();
        assert_eq!(odd, "a.svg: element 'bad\\u{1b}[31mid\\u{a}': x");
        let quoted = Error::input("a.svg", "crosses 'f\u{7}'").with_hint("rename '\u{1b}'");
        assert_eq!(
            quoted.to_string(),
            "a.svg: crosses 'f\\u{7}' (hint: rename '\\u{1b}')"
        );
        assert_eq!(printable_line(&printable_line("a\u{1b}")), "a\\u{1b}");
    }

    #[test]
    fn drawings_read_as_placeholders_until_named() {
        let e = Error::at(Drawings::Pair, "feature-eye", "folds");
        assert_eq!(
            e.to_string(),
            "<source> → <target>: element 'feature-eye': folds"
        );
        let named = e.with_files("a.svg", "b.svg");
        assert_eq!(
            named.to_string(),
            "a.svg → b.svg: element 'feature-eye': folds"
        );
        // Named once: a second naming changes nothing, nor does naming a known file.
        assert_eq!(named.clone().with_files("x", "y"), named);
        let known = Error::input("c.svg", "x");
        assert_eq!(known.clone().with_files("a.svg", "b.svg"), known);
        // A file literally called "<source>" is a file, not a placeholder.
        let odd = Error::input("<source>", "x").with_files("a.svg", "b.svg");
        assert_eq!(odd.to_string(), "<source>: x");
    }
}
