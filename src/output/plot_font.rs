//! The font every chart draws with, shipped in `assets/fonts` so plots look the same on any
//! machine (plotters' `ab_glyph` backend has no system fonts).

use std::sync::Once;

use plotters::style::FontStyle;

const FONT: &[u8] = include_bytes!("../../assets/fonts/DejaVuSans.ttf");
static REGISTER_FONT: Once = Once::new();

/// Registers the shipped font as plotters' "sans-serif" (once per process).
pub(crate) fn register_plot_font() {
    REGISTER_FONT.call_once(|| {
        let _ = plotters::style::register_font("sans-serif", FontStyle::Normal, FONT);
    });
}
