//! `simulate --html`: the self-contained HTML report. Its output is reserved with the others
//! before any work; the renderer is started then too, and where there is no GPU adapter the
//! page goes without renders and says why. The page itself is the library's
//! (`vpcut::to_html`); this module gathers what it shows.

use crate::cli::output::{Allow, Outputs, Slot};
use crate::cli::term::Progress;
use std::path::Path;

/// The renders' size on the page (a width in multiples of 64, as the renderer wants; the
/// page shows them 720 pixels wide).
const RENDER_SIZE: (u32, u32) = (768, 576);

/// An HTML report to write.
pub(crate) struct Html {
    slot: Slot,
    /// Its own renderer, when the run starts none for `--png`/`--renders`.
    renderer: Option<vpcut::Renderer>,
    /// Why there are no renders.
    note: Option<String>,
}

impl Html {
    /// Reserve the output and, unless the run has a renderer already, start one (no adapter
    /// is no error: the page says so).
    pub(crate) fn prepare(
        path: &Path,
        outs: &mut Outputs,
        progress: &Progress,
        has_renderer: bool,
    ) -> anyhow::Result<Html> {
        let slot = outs.file(path, "--html", Allow::FileOrStdout)?;
        let (renderer, note) = if has_renderer {
            (None, None)
        } else {
            match progress.stage("starting the renderer", || {
                crate::cli::quiet::gpu_quiet(|| vpcut::Renderer::new(4))
            }) {
                Ok(r) => match r.check(&options(vpcut::View::Iso)) {
                    Ok(()) => (Some(r), None),
                    Err(e) => (None, Some(format!("No renders: {e}."))),
                },
                Err(e) => (None, Some(format!("No renders: {e}."))),
            }
        };
        Ok(Html {
            slot,
            renderer,
            note,
        })
    }

    /// Render, place the findings and write the page into its slot. `plots` are the
    /// developed view's, the section's and the trace's PNGs, the section and the trace at
    /// `angle` (rad); `renderer` the run's own, if it has one.
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn write(
        &self,
        job: &vpcut::Job,
        outcome: &vpcut::Outcome,
        scene: &vpcut::Scene,
        plots: [Vec<u8>; 3],
        angle: f64,
        renderer: Option<&vpcut::Renderer>,
        outs: &mut Outputs,
        progress: &Progress,
    ) -> anyhow::Result<()> {
        let report = &outcome.report;
        let mut renders = Vec::new();
        if let Some(r) = self.renderer.as_ref().or(renderer) {
            for view in vpcut::View::ALL {
                let png = progress.stage(
                    &format!("rendering the {} view for the page", view.name()),
                    || r.png(scene, &options(view)),
                )?;
                renders.push(vpcut::HtmlPicture {
                    caption: format!("{} view (GPU render)", view.name()),
                    png,
                });
            }
        }
        let places: Vec<vpcut::FindingPlace> = report
            .findings
            .iter()
            .map(|f| vpcut::FindingPlace {
                point: vpcut::finding_point(outcome, job, f),
            })
            .collect();
        let [developed, section, trace] = plots;
        let deg = angle.to_degrees().rem_euclid(360.0);
        let plots = [
            vpcut::HtmlPicture {
                caption: "developed view: the deviation over angle x z, in bands of the tolerance"
                    .into(),
                png: developed,
            },
            vpcut::HtmlPicture {
                caption: format!("axial section at {deg:.1}\u{b0}: machined and ideal profile"),
                png: section,
            },
            vpcut::HtmlPicture {
                caption: format!(
                    "deviation along z on the generators at {deg:.1}\u{b0} and every 90\u{b0} on, with the tolerance and the report's worst places"
                ),
                png: trace,
            },
        ];
        let text = progress.stage("writing the HTML report", || {
            vpcut::to_html(&vpcut::HtmlPage {
                report,
                scene,
                places: &places,
                plots: &plots,
                renders: &renders,
                note: self.note.as_deref(),
            })
        });
        outs.put(self.slot, text.as_bytes())
    }
}

/// The options of a render on the page.
fn options(view: vpcut::View) -> vpcut::RenderOptions {
    vpcut::RenderOptions {
        view,
        width: RENDER_SIZE.0,
        height: RENDER_SIZE.1,
        edges: false,
        toolpath: vpcut::ToolpathMode::Auto,
    }
}
