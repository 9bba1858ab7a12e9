//! `report.html`: one page a person opens after a run: the numbers, the pictures beside them,
//! and the fabric the run used, in KES and SI units. It links its pictures by file name, so the
//! output folder can be moved or opened offline as it is.

use std::path::Path;

use super::OutputError;

/// What a report shows.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Report {
    /// Page title, e.g. the scene's name.
    pub title: String,
    /// The headline figures: (what, value with its unit).
    pub figures: Vec<(String, String)>,
    /// The run's printed summary, shown as it was printed.
    pub summary: String,
    /// Pictures in the output folder: (file name, caption).
    pub pictures: Vec<(String, String)>,
    /// The fabric's sheet (`crate::output::fabric_sheet`), if its KES values are known.
    pub fabric_sheet: Option<String>,
    /// The draped mesh as binary glTF, shown in an interactive 3D view: its file's path
    /// relative to the report (e.g. `final.glb`) and its bytes.
    pub glb: Option<(String, Vec<u8>)>,
    /// Tables after the pictures, e.g. one row per seed of a repeat.
    pub tables: Vec<ReportTable>,
    /// Preformatted text after the tables: (heading, text), e.g. a study's table.
    pub texts: Vec<(String, String)>,
}

/// A table of a report.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ReportTable {
    /// Heading above the table.
    pub caption: String,
    /// Column names, with their units.
    pub header: Vec<String>,
    /// Rows of cells.
    pub rows: Vec<Vec<String>>,
}

/// The vendored three.js files the 3D view loads, written into `viewer/` beside the report
/// (`assets/viewer/README.md`).
const VIEWER_FILES: [(&str, &str); 3] = [
    ("three.min.js", include_str!("../../assets/viewer/three.min.js")),
    (
        "OrbitControls.js",
        include_str!("../../assets/viewer/OrbitControls.js"),
    ),
    ("GLTFLoader.js", include_str!("../../assets/viewer/GLTFLoader.js")),
];

/// The page's script that shows `glb` (base64) in the element `view3d`: the cloth lit from
/// above, turned with the mouse (OrbitControls), framed on its bounding box.
const VIEWER_SCRIPT: &str = r#"
(function () {
  const box = document.getElementById('view3d');
  const bytes = Uint8Array.from(atob(GLB_BASE64), c => c.charCodeAt(0));
  const renderer = new THREE.WebGLRenderer({ antialias: true, preserveDrawingBuffer: true });
  renderer.setSize(box.clientWidth, box.clientHeight);
  renderer.setClearColor(0xffffff);
  box.appendChild(renderer.domElement);
  const scene = new THREE.Scene();
  scene.add(new THREE.HemisphereLight(0xffffff, 0x667788, 0.8));
  const sun = new THREE.DirectionalLight(0xffffff, 0.7);
  sun.position.set(0.5, 1.0, 0.8);
  scene.add(sun);
  const camera = new THREE.PerspectiveCamera(35, box.clientWidth / box.clientHeight, 0.001, 100);
  const controls = new THREE.OrbitControls(camera, renderer.domElement);
  new THREE.GLTFLoader().parse(bytes.buffer, '', function (gltf) {
    scene.add(gltf.scene);
    const bounds = new THREE.Box3().setFromObject(gltf.scene);
    const centre = bounds.getCenter(new THREE.Vector3());
    const size = bounds.getSize(new THREE.Vector3()).length();
    camera.position.set(centre.x + 0.6 * size, centre.y + 0.7 * size, centre.z + 0.9 * size);
    controls.target.copy(centre);
    controls.update();
    // Record how much of the view the cloth covers (pixels not the white background), so a
    // test in a headless browser can tell a drawn cloth from an empty canvas.
    renderer.render(scene, camera);
    const gl = renderer.getContext();
    const w = gl.drawingBufferWidth, h = gl.drawingBufferHeight;
    const px = new Uint8Array(w * h * 4);
    gl.readPixels(0, 0, w, h, gl.RGBA, gl.UNSIGNED_BYTE, px);
    let covered = 0;
    for (let i = 0; i < px.length; i += 4) {
      if (px[i] < 250 || px[i + 1] < 250 || px[i + 2] < 250) covered++;
    }
    box.dataset.coverage = (covered / (w * h)).toFixed(3);
    box.dataset.loaded = 'true';
    (function frame() { renderer.render(scene, camera); requestAnimationFrame(frame); })();
  }, function (error) { console.error(error); });
})();
"#;

/// `text` safe inside HTML.
fn escape(text: &str) -> String {
    text.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

impl Report {
    /// The page's HTML.
    pub fn html(&self) -> String {
        let mut page = String::new();
        page.push_str("<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n");
        page.push_str(&format!("<title>{} — kes-cloth</title>\n", escape(&self.title)));
        page.push_str(
            "<style>\nbody { font-family: sans-serif; margin: 2em auto; max-width: 1100px; color: #222; }\n\
             table { border-collapse: collapse; margin: 1em 0; }\n\
             td, th { border-bottom: 1px solid #ddd; padding: 0.3em 1em 0.3em 0; text-align: left; }\n\
             figure { display: inline-block; margin: 0 1em 1em 0; vertical-align: top; }\n\
             figure img { max-width: 520px; border: 1px solid #ccc; }\n\
             pre { background: #f6f6f6; padding: 1em; overflow-x: auto; }\n</style>\n</head>\n<body>\n",
        );
        // Script errors on the page are kept on <body data-errors>, where a reader's browser
        // console and a headless test can both find them.
        page.push_str(
            "<script>\nfunction noteError(text) { document.body.dataset.errors = (document.body.dataset.errors || '') + text + '\\n'; }\n\
             window.addEventListener('error', function (e) { noteError(e.message); });\n\
             (function () { const original = console.error; console.error = function () { noteError(Array.from(arguments).join(' ')); original.apply(console, arguments); }; })();\n</script>\n",
        );
        page.push_str(&format!("<h1>{}</h1>\n", escape(&self.title)));
        page.push_str("<table id=\"figures\">\n");
        for (what, value) in &self.figures {
            page.push_str(&format!(
                "<tr><th>{}</th><td>{}</td></tr>\n",
                escape(what),
                escape(value)
            ));
        }
        page.push_str("</table>\n");
        for (file, caption) in &self.pictures {
            page.push_str(&format!(
                "<figure><img src=\"{}\" alt=\"{}\"><figcaption>{}</figcaption></figure>\n",
                escape(file),
                escape(caption),
                escape(caption)
            ));
        }
        if let Some((file, glb)) = &self.glb {
            use base64::Engine as _;
            page.push_str(&format!(
                "<h2>The draped cloth in 3D</h2>\n<p>Drag to turn, scroll to zoom; the mesh is <a href=\"{0}\">{0}</a>.</p>\n",
                escape(file)
            ));
            page.push_str(
                "<div id=\"view3d\" style=\"width: 100%; height: 480px; border: 1px solid #ccc\"></div>\n",
            );
            for (file, _) in VIEWER_FILES {
                page.push_str(&format!("<script src=\"viewer/{file}\"></script>\n"));
            }
            page.push_str(&format!(
                "<script>\nconst GLB_BASE64 = \"{}\";\n{VIEWER_SCRIPT}</script>\n",
                base64::engine::general_purpose::STANDARD.encode(glb)
            ));
        }
        for table in &self.tables {
            page.push_str(&format!("<h2>{}</h2>\n<table>\n<tr>", escape(&table.caption)));
            for name in &table.header {
                page.push_str(&format!("<th>{}</th>", escape(name)));
            }
            page.push_str("</tr>\n");
            for row in &table.rows {
                page.push_str("<tr>");
                for cell in row {
                    page.push_str(&format!("<td>{}</td>", escape(cell)));
                }
                page.push_str("</tr>\n");
            }
            page.push_str("</table>\n");
        }
        for (heading, text) in &self.texts {
            page.push_str(&format!(
                "<h2>{}</h2>\n<pre>{}</pre>\n",
                escape(heading),
                escape(text)
            ));
        }
        if !self.summary.is_empty() {
            page.push_str("<h2>Run</h2>\n");
            page.push_str(&format!("<pre id=\"summary\">{}</pre>\n", escape(&self.summary)));
        }
        if let Some(sheet) = &self.fabric_sheet {
            page.push_str("<h2>Fabric</h2>\n");
            page.push_str(&format!("<pre id=\"fabric\">{}</pre>\n", escape(sheet)));
        }
        page.push_str("</body>\n</html>\n");
        page
    }

    /// Writes `dir/report.html`, and the viewer's scripts into `dir/viewer/` if it shows a mesh.
    pub fn write(&self, dir: &Path) -> Result<(), OutputError> {
        if self.glb.is_some() {
            let viewer = dir.join("viewer");
            std::fs::create_dir_all(&viewer).map_err(|e| OutputError::new(&viewer, e))?;
            for (file, text) in VIEWER_FILES {
                let path = viewer.join(file);
                std::fs::write(&path, text).map_err(|e| OutputError::new(&path, e))?;
            }
        }
        let path = dir.join("report.html");
        std::fs::write(&path, self.html()).map_err(|e| OutputError::new(&path, e))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Text from a fabric file or a scene name cannot break the page.
    #[test]
    fn text_is_escaped() {
        let report = Report {
            title: "a <b> & \"c\"".into(),
            ..Report::default()
        };
        let html = report.html();
        assert!(
            html.contains("<h1>a &lt;b&gt; &amp; &quot;c&quot;</h1>"),
            "{html}"
        );
    }
}
