//! The font of crmorph's own pictures: a subset of DejaVu Sans bundled in the crate
//! (`assets/fonts/`, with its licence), so that the text crmorph writes into its pictures — the
//! captions of `crmorph inspect` — renders to the same pixels on every machine. No system font
//! is read for these pictures; the user's drawings keep using the system fonts
//! (`artwork::Scene`).

use std::sync::{Arc, OnceLock};

/// DejaVu Sans 2.37, printable ASCII and a few typographic characters (see
/// `assets/fonts/README.md` for how the subset was made).
const DEJAVU_SANS_SUBSET: &[u8] = include_bytes!("../../assets/fonts/DejaVuSans-subset.ttf");

/// The family name of the bundled font, for the `font-family` of crmorph's own text.
pub(crate) const FAMILY: &str = "DejaVu Sans";

/// A font database holding only the bundled font, which is also every generic family
/// (`sans-serif`, `serif`, `monospace`, …), built once per process.
pub(crate) fn bundled_fontdb() -> Arc<usvg::fontdb::Database> {
    static DB: OnceLock<Arc<usvg::fontdb::Database>> = OnceLock::new();
    DB.get_or_init(|| {
        let mut db = usvg::fontdb::Database::new();
        db.load_font_data(DEJAVU_SANS_SUBSET.to_vec());
        db.set_sans_serif_family(FAMILY);
        db.set_serif_family(FAMILY);
        db.set_monospace_family(FAMILY);
        db.set_cursive_family(FAMILY);
        db.set_fantasy_family(FAMILY);
        Arc::new(db)
    })
    .clone()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_bundled_font_answers_for_every_generic_family() {
        let db = bundled_fontdb();
        assert_eq!(db.len(), 1, "the subset is one face");
        for family in [
            usvg::fontdb::Family::SansSerif,
            usvg::fontdb::Family::Serif,
            usvg::fontdb::Family::Monospace,
            usvg::fontdb::Family::Name(FAMILY),
        ] {
            let q = usvg::fontdb::Query {
                families: &[family],
                ..usvg::fontdb::Query::default()
            };
            assert!(db.query(&q).is_some(), "{family:?}");
        }
    }
}
