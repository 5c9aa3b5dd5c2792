//! A figure as PNG: the SVG rendered by resvg (pure Rust, no system libraries), with the
//! system's fonts (found by fontdb; none means no PNG, said in words, since a figure without
//! its labels would mislead). 1.5× the view box: 1920 × 1080, a full-HD slide.

use std::sync::OnceLock;

use resvg::{tiny_skia, usvg};

/// Pixels per view-box unit: 1280 × 720 becomes 1920 × 1080.
pub const PNG_SCALE: f32 = 1.5;

/// The sans-serif families tried, in order, for the figures' `sans-serif`.
const SANS_SERIF: [&str; 5] = [
    "DejaVu Sans",
    "Liberation Sans",
    "Noto Sans",
    "Helvetica",
    "Arial",
];

/// The system's fonts, loaded once (reading them takes tens of milliseconds).
fn fonts() -> &'static Result<std::sync::Arc<usvg::fontdb::Database>, String> {
    static FONTS: OnceLock<Result<std::sync::Arc<usvg::fontdb::Database>, String>> =
        OnceLock::new();
    FONTS.get_or_init(|| {
        let mut database = usvg::fontdb::Database::new();
        database.load_system_fonts();
        if database.is_empty() {
            return Err(
                "no fonts found on this system, and a PNG without its labels would \
                        mislead: write the SVG instead"
                    .into(),
            );
        }
        let has = |family: &str| {
            database
                .faces()
                .any(|face| face.families.iter().any(|(name, _)| name == family))
        };
        let sans = SANS_SERIF.into_iter().find(|f| has(f)).map(str::to_string);
        let any = database
            .faces()
            .next()
            .and_then(|face| face.families.first().map(|(name, _)| name.clone()));
        if let Some(family) = sans.or(any) {
            database.set_sans_serif_family(family);
        }
        Ok(std::sync::Arc::new(database))
    })
}

/// The PNG of an SVG figure, at [`PNG_SCALE`], or why there is none.
pub fn svg_to_png(svg: &str) -> Result<Vec<u8>, String> {
    let fonts = fonts().as_ref().map_err(Clone::clone)?;
    let options = usvg::Options {
        fontdb: fonts.clone(),
        ..usvg::Options::default()
    };
    let tree = usvg::Tree::from_str(svg, &options)
        .map_err(|e| format!("internal error: the figure's SVG does not parse: {e}"))?;
    let size = tree
        .size()
        .to_int_size()
        .scale_by(PNG_SCALE)
        .ok_or("internal error: the figure has no size")?;
    let mut pixmap = tiny_skia::Pixmap::new(size.width(), size.height())
        .ok_or("internal error: no room for the picture")?;
    resvg::render(
        &tree,
        tiny_skia::Transform::from_scale(PNG_SCALE, PNG_SCALE),
        &mut pixmap.as_mut(),
    );
    pixmap
        .encode_png()
        .map_err(|e| format!("internal error: PNG encoding failed: {e}"))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_notice_figure_renders_at_full_hd_with_its_text() {
        use crate::figure::{FigurePanel, notice_figure};
        let svg = notice_figure(FigurePanel::EpsError, "A title", "nothing to plot");
        let Ok(png) = svg_to_png(&svg) else {
            // A machine without fonts: refused in words, tested in `fonts`' own message.
            assert!(fonts().is_err());
            return;
        };
        assert_eq!(&png[1..4], b"PNG");
        // Width and height from the IHDR chunk.
        let width = u32::from_be_bytes(png[16..20].try_into().unwrap());
        let height = u32::from_be_bytes(png[20..24].try_into().unwrap());
        assert_eq!((width, height), (1920, 1080));
        // Text was drawn: the picture has dark pixels besides the white page.
        let blank = svg_to_png(
            r#"<svg xmlns="http://www.w3.org/2000/svg" width="1280" height="720"><rect width="1280" height="720" fill="white"/></svg>"#,
        )
        .unwrap();
        assert!(
            png.len() > blank.len() + 1000,
            "{} vs {}",
            png.len(),
            blank.len()
        );
    }
}
