//! Errors of the viewer.

/// Something the viewer could not do.
#[derive(Debug, thiserror::Error)]
pub enum Error {
    #[error(
        "no display to open a window on ({0}).\n\
         `wavetrace view` needs one; without a display, render headless with\n  \
         wavetrace render SCENE.xml -o out.exr\n\
         or watch the render converge in tev (https://github.com/Tom94/tev) with\n  \
         wavetrace render SCENE.xml --tev [HOST:PORT]"
    )]
    NoDisplay(String),
    #[error(
        "the Vulkan driver cannot present to a window ({0}).\n\
         A driver built without a window-system platform (for example lavapipe from\n\
         tools/lavapipe.sh) renders but cannot show a window: run `wavetrace view` on\n\
         the system's driver (unset VK_ICD_FILENAMES), or render headless with\n  \
         wavetrace render SCENE.xml -o out.exr"
    )]
    NoPresentation(String),
    #[error(transparent)]
    Gpu(#[from] crate::gpu::Error),
    #[error(transparent)]
    Render(#[from] crate::render::Error),
    #[error(transparent)]
    Image(#[from] crate::image::Error),
    #[error("{0}")]
    Options(String),
}

/// Result alias of the viewer.
pub type Result<T> = std::result::Result<T, Error>;
