//! Ids that almost follow a convention: `Boundary`, `feature_eye`, `featur-eye`, `Controls`.
//!
//! Control geometry is found by exact id (DESIGN §1), so a typo or a capital letter silently
//! turns a curve into plain artwork, and the error that follows — if any — is about something
//! else (an anchor too far from its curve, a mapping that folds). Reading a drawing records each
//! such near miss with the id it most likely meant, for the errors and notes that name it.

use super::xml::Element;
use super::ControlIds;

/// An element id that differs from a control convention only in case, in the separator
/// (`_`, space or none for `-`), or by a small typo.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct NearMiss {
    /// The id as written.
    pub id: String,
    /// The id it most likely meant, following the convention exactly.
    pub meant: String,
}

impl NearMiss {
    /// A note for a drawing read without complaint: "element 'Controls' is not the convention
    /// id 'controls' (ids are case-sensitive), so it is not read as one; rename it to …".
    pub fn note(&self) -> String {
        format!(
            "element '{}' is not read as '{}' ({}); rename it if it was meant to be",
            self.id,
            self.meant,
            self.how()
        )
    }

    /// How `id` differs from `meant`, for a hint: "differs only in case", "is a typo".
    pub fn how(&self) -> &'static str {
        if self.id.eq_ignore_ascii_case(&self.meant) {
            "ids are case-sensitive"
        } else {
            "it does not follow the convention exactly"
        }
    }

    /// A hint naming the near miss in `file`: "FILE has 'Boundary' (ids are case-sensitive);
    /// rename it to 'boundary'".
    pub fn hint(&self, file: &str) -> String {
        format!(
            "{file} has '{}' ({}): rename it to '{}'",
            self.id,
            self.how(),
            self.meant
        )
    }
}

/// The largest edit distance accepted as a typo for a word of `len` characters: one for short
/// words, two from eight characters on (`boundary`, `skeleton`, `controls`).
fn typo_budget(len: usize) -> usize {
    match len {
        0..=3 => 0,
        4..=7 => 1,
        _ => 2,
    }
}

/// Whether `written` is `word` with a different case or a small typo (but not `word` itself).
pub fn resembles(written: &str, word: &str) -> bool {
    if written == word || written.is_empty() || word.is_empty() {
        return false;
    }
    let (a, b) = (written.to_lowercase(), word.to_lowercase());
    a == b || strsim::damerau_levenshtein(&a, &b) <= typo_budget(word.chars().count())
}

/// The convention id `id` most likely meant, or `None` when it follows one exactly or is
/// nothing like one.
pub(crate) fn meant(id: &str, ids: &ControlIds) -> Option<String> {
    // Whole ids: the boundary, the skeleton and the guides' group.
    for word in [&ids.boundary, &ids.skeleton, &ids.guides_group] {
        if id == word.as_str() {
            return None;
        }
        if resembles(id, word) {
            return Some(word.clone());
        }
    }
    // Prefixed ids: `feature-NAME`, `anchor-NAME`, `skeleton-NAME`. The prefix's word (its
    // text before a trailing separator) followed by `-`, `_`, a space or nothing, then a name.
    let skeleton_prefix = format!("{}-", ids.skeleton);
    for prefix in [&ids.feature_prefix, &ids.anchor_prefix, &skeleton_prefix] {
        if id.starts_with(prefix.as_str()) && id.len() > prefix.len() {
            return None;
        }
        let word = prefix.trim_end_matches(['-', '_']);
        if word.is_empty() {
            continue;
        }
        for (k, c) in id.char_indices() {
            if !matches!(c, '-' | '_' | ' ') {
                continue;
            }
            let (head, name) = (&id[..k], &id[k + c.len_utf8()..]);
            if name.is_empty() {
                break;
            }
            if head == word && c != '-' || resembles(head, word) {
                return Some(format!("{prefix}{name}"));
            }
            break;
        }
    }
    None
}

/// Every near miss among the ids of `root`'s elements, in document order.
pub(crate) fn near_misses(root: &Element, ids: &ControlIds) -> Vec<NearMiss> {
    let mut out = Vec::new();
    let mut stack = vec![root];
    while let Some(el) = stack.pop() {
        if let Some(id) = el.id() {
            if let Some(m) = meant(id, ids) {
                out.push(NearMiss {
                    id: id.to_string(),
                    meant: m,
                });
            }
        }
        stack.extend(el.children.iter().rev());
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn m(id: &str) -> Option<String> {
        meant(id, &ControlIds::default())
    }

    #[test]
    fn case_separators_and_typos_are_near_misses() {
        for (id, want) in [
            ("Boundary", "boundary"),
            ("BOUNDARY", "boundary"),
            ("boundry", "boundary"),
            ("bounday", "boundary"),
            ("Controls", "controls"),
            ("Skeleton", "skeleton"),
            ("Feature-eye", "feature-eye"),
            ("feature_eye", "feature-eye"),
            ("featur-eye", "feature-eye"),
            ("feautre-left-eye", "feature-left-eye"),
            ("features-eye", "feature-eye"),
            ("Anchor-tip", "anchor-tip"),
            ("anchor_tip", "anchor-tip"),
            ("achor-tip", "anchor-tip"),
            ("Skeleton-arm", "skeleton-arm"),
            ("skeleton_arm", "skeleton-arm"),
        ] {
            assert_eq!(m(id).as_deref(), Some(want), "{id}");
        }
    }

    #[test]
    fn conventions_and_unrelated_ids_are_not() {
        for id in [
            "boundary",
            "controls",
            "skeleton",
            "feature-eye",
            "feature-Eye",
            "anchor-tip",
            "skeleton-arm",
            "bound",
            "skin",
            "leafg",
            "path12",
            "layer-1",
            "future-eye",
            "g",
            "feature-",
            "anchors",
        ] {
            assert_eq!(m(id), None, "{id}");
        }
    }

    #[test]
    fn renamed_conventions_are_followed() {
        let ids = ControlIds {
            boundary: "outline".into(),
            feature_prefix: "f:".into(),
            ..ControlIds::default()
        };
        assert_eq!(meant("Outline", &ids).as_deref(), Some("outline"));
        assert_eq!(meant("boundary", &ids), None);
        assert_eq!(meant("f:eye", &ids), None);
    }

    #[test]
    fn hints_say_how_the_id_differs() {
        let n = NearMiss {
            id: "Boundary".into(),
            meant: "boundary".into(),
        };
        assert_eq!(
            n.hint("b.svg"),
            "b.svg has 'Boundary' (ids are case-sensitive): rename it to 'boundary'"
        );
        let n = NearMiss {
            id: "featur-eye".into(),
            meant: "feature-eye".into(),
        };
        assert!(n
            .hint("b.svg")
            .contains("does not follow the convention exactly"));
    }
}
