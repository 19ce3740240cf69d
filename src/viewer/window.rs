//! The GLFW window: opening it (or saying why there is none), the Vulkan surface
//! extensions and surface it needs, its events.
//!
//! GLFW 3.4 loads libX11 and the Vulkan loader itself when it starts, so nothing
//! here needs a display or X11 until `view` opens a window: `render` and the tests
//! run without either.

use std::sync::Mutex;

use glfw::{ClientApiHint, GlfwReceiver, PWindow, WindowEvent, WindowHint, WindowMode};

use super::error::{Error, Result};

/// The last error GLFW reported (its error callback takes no context).
static LAST_GLFW_ERROR: Mutex<String> = Mutex::new(String::new());

fn last_glfw_error() -> String {
    let last = LAST_GLFW_ERROR
        .lock()
        .map(|e| e.clone())
        .unwrap_or_default();
    if last.is_empty() {
        "GLFW reported no error".to_string()
    } else {
        last
    }
}

/// Why there is no display to open a window on, if that can be told from the
/// environment: neither `DISPLAY` nor `WAYLAND_DISPLAY` is set.
pub fn missing_display() -> Option<String> {
    let set = |name: &str| std::env::var_os(name).is_some_and(|v| !v.is_empty());
    (!set("DISPLAY") && !set("WAYLAND_DISPLAY"))
        .then(|| "neither DISPLAY nor WAYLAND_DISPLAY is set".to_string())
}

/// A window with no graphics API of its own (Vulkan presents to it).
pub struct Window {
    // Field order is drop order: the window goes before GLFW terminates.
    pub window: PWindow,
    pub events: GlfwReceiver<(f64, WindowEvent)>,
    pub glfw: glfw::Glfw,
}

impl Window {
    /// Opens a `width` x `height` window titled `title`, with every event the
    /// controls use polled.
    pub fn open(title: &str, width: u32, height: u32) -> Result<Window> {
        if let Some(reason) = missing_display() {
            return Err(Error::NoDisplay(reason));
        }
        let mut glfw = glfw::init(|error: glfw::Error, description: String| {
            if let Ok(mut last) = LAST_GLFW_ERROR.lock() {
                *last = format!("{description} ({error:?})");
            }
        })
        .map_err(|_| Error::NoDisplay(format!("GLFW could not start: {}", last_glfw_error())))?;
        if !glfw.vulkan_supported() {
            return Err(Error::NoPresentation(format!(
                "GLFW finds no Vulkan loader and driver able to present to windows: {}",
                last_glfw_error()
            )));
        }
        glfw.window_hint(WindowHint::ClientApi(ClientApiHint::NoApi));
        glfw.window_hint(WindowHint::Resizable(true));
        let (mut window, events) = glfw
            .create_window(width.max(1), height.max(1), title, WindowMode::Windowed)
            .ok_or_else(|| {
                Error::NoDisplay(format!(
                    "GLFW could not open a window: {}",
                    last_glfw_error()
                ))
            })?;
        window.set_key_polling(true);
        window.set_mouse_button_polling(true);
        window.set_cursor_pos_polling(true);
        window.set_scroll_polling(true);
        window.set_framebuffer_size_polling(true);
        window.set_close_polling(true);
        window.set_refresh_polling(true);
        Ok(Window {
            window,
            events,
            glfw,
        })
    }

    /// The Vulkan instance extensions presenting to this window needs.
    pub fn instance_extensions(&self) -> Result<Vec<String>> {
        self.glfw.get_required_instance_extensions().ok_or_else(|| {
            Error::NoPresentation(format!(
                "GLFW names no Vulkan extensions to present with: {}",
                last_glfw_error()
            ))
        })
    }

    /// Makes this window's Vulkan surface on the instance whose raw handle is
    /// `instance`; returns the raw surface handle.
    pub fn create_surface(&self, instance: u64) -> std::result::Result<u64, String> {
        let mut surface: glfw::ffi::VkSurfaceKHR = std::ptr::null_mut();
        // SAFETY: `instance` is a live VkInstance (Device::with_surface passes its
        // own), created with the extensions `instance_extensions` named; the surface
        // is destroyed with that device, before this window.
        let result = unsafe {
            self.window.create_window_surface(
                instance as usize as glfw::ffi::VkInstance,
                std::ptr::null(),
                &mut surface,
            )
        };
        if result != 0 || surface.is_null() {
            return Err(format!(
                "vkCreateSurfaceKHR for the window failed (VkResult {result}): {}",
                last_glfw_error()
            ));
        }
        Ok(surface as usize as u64)
    }

    /// The size of the window's drawable area in pixels.
    pub fn framebuffer_size(&self) -> (u32, u32) {
        let (w, h) = self.window.get_framebuffer_size();
        (w.max(0) as u32, h.max(0) as u32)
    }
}
