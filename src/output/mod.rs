//! What a simulation is shown as: the 3D scene ([`scene`], built by [`mesh`] from the
//! whole grid or while the columns stream, [`stream`]), its binary glTF ([`glb`]), the GPU
//! renders ([`render`]) and the pictures that need no GPU ([`plot`]), the tool in them
//! ([`tool`]), and the
//! self-contained HTML report with its WebGL view ([`html`]).

pub(crate) mod glb;
pub(crate) mod html;
pub(crate) mod mesh;
pub(crate) mod plot;
pub(crate) mod profile;
pub(crate) mod render;
pub(crate) mod scene;
pub(crate) mod stream;
pub(crate) mod tool;
