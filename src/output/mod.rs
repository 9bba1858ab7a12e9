//! What a run writes: `metrics.json`, the final mesh `final.obj`, the top view `top.png`.

mod fabric_sheet;
mod mesh_glb;
mod mesh_obj;
mod metrics;
mod plot_font;
mod repeat_plot;
mod report_html;
mod side_view;
mod top_view;

use std::path::PathBuf;

pub use fabric_sheet::{fabric_sheet, number};
pub use mesh_glb::{glb_bytes, write_glb};
pub use mesh_obj::write_obj;
pub use metrics::{EffectCost, FailureReport, Metrics, SolveSplit};
pub(crate) use plot_font::register_plot_font;
pub use repeat_plot::write_repeat_plot;
pub use report_html::{Report, ReportTable};
pub use side_view::write_side_view;
pub use top_view::{TopViewOutline, write_top_view};

/// Writing an output file failed.
#[derive(Debug, thiserror::Error)]
#[error("{}: cannot write: {message}", path.display())]
pub struct OutputError {
    /// The file being written.
    pub path: PathBuf,
    /// What went wrong.
    pub message: String,
}

impl OutputError {
    pub(crate) fn new(path: &std::path::Path, e: impl std::fmt::Display) -> Self {
        Self {
            path: path.to_path_buf(),
            message: e.to_string(),
        }
    }
}
