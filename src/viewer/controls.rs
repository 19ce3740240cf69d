//! What the keys and the mouse do, as pbrt-v4's viewer has them plus a few:
//!
//! | input             | action                                               |
//! |-------------------|------------------------------------------------------|
//! | W / S             | move forward / back                                  |
//! | A / D             | move left / right                                    |
//! | Q / E             | move down / up                                       |
//! | arrow keys        | turn (2 degrees a press)                             |
//! | left mouse drag   | orbit the point the camera looks at                  |
//! | scroll            | field of view (10% a click)                          |
//! | = / -             | double / halve the move step                         |
//! | ] / [             | exposure up / down half a stop                       |
//! | R                 | back to the scene's camera                           |
//! | F12 or P          | save the current image as EXR and PNG                |
//! | Esc               | quit                                                 |
//!
//! Every camera change restarts the accumulation; exposure only changes how the
//! film is shown.

use glam::Vec3;
use glfw::{Action, Key, MouseButton, WindowEvent};

use super::camera::CameraRig;

/// Degrees an arrow key turns the camera.
const TURN_DEG: f32 = 2.0;
/// Degrees of orbit per pixel of mouse drag.
const ORBIT_DEG_PER_PIXEL: f32 = 0.25;
/// Stops of exposure per press of [ or ].
pub const EXPOSURE_STEP: f32 = 0.5;

/// What an input asks of the viewer beyond moving the camera.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Request {
    Save,
    Quit,
}

/// The state of the controls: the camera, the exposure, a drag in progress.
pub struct Controls {
    pub camera: CameraRig,
    /// Stops; the display multiplies by 2^exposure.
    pub exposure: f32,
    /// The cursor at the last drag event, while the left button is held.
    drag: Option<(f64, f64)>,
    cursor: (f64, f64),
}

/// What one event changed.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Changed {
    /// The camera moved: restart the accumulation.
    pub camera: bool,
    /// The exposure changed: show the film again.
    pub exposure: bool,
    pub request: Option<Request>,
}

impl Controls {
    pub fn new(camera: CameraRig, exposure: f32) -> Controls {
        Controls {
            camera,
            exposure,
            drag: None,
            cursor: (0.0, 0.0),
        }
    }

    /// Applies one window event.
    pub fn handle(&mut self, event: &WindowEvent) -> Changed {
        let mut changed = Changed::default();
        match *event {
            WindowEvent::Key(key, _, Action::Press | Action::Repeat, _) => {
                self.key(key, &mut changed)
            }
            WindowEvent::MouseButton(MouseButton::Button1, action, _) => {
                self.drag = (action == Action::Press).then_some(self.cursor);
            }
            WindowEvent::CursorPos(x, y) => {
                self.cursor = (x, y);
                if let Some((x0, y0)) = self.drag {
                    let (dx, dy) = ((x - x0) as f32, (y - y0) as f32);
                    if dx != 0.0 || dy != 0.0 {
                        // The scene turns as if grabbed: dragging right, the camera
                        // goes round to its left (turning right to keep it in view);
                        // dragging down, over its top (looking down).
                        self.camera
                            .orbit(dx * ORBIT_DEG_PER_PIXEL, -dy * ORBIT_DEG_PER_PIXEL);
                        changed.camera = true;
                    }
                    self.drag = Some((x, y));
                }
            }
            WindowEvent::Scroll(_, y) if y != 0.0 => {
                self.camera.zoom(y as f32);
                changed.camera = true;
            }
            WindowEvent::Close => changed.request = Some(Request::Quit),
            _ => {}
        }
        changed
    }

    fn key(&mut self, key: Key, changed: &mut Changed) {
        let c = &mut self.camera;
        let mut moved = true;
        match key {
            Key::W => c.translate(Vec3::Z),
            Key::S => c.translate(-Vec3::Z),
            Key::D => c.translate(Vec3::X),
            Key::A => c.translate(-Vec3::X),
            Key::E => c.translate(Vec3::Y),
            Key::Q => c.translate(-Vec3::Y),
            Key::Right => c.turn(TURN_DEG, 0.0),
            Key::Left => c.turn(-TURN_DEG, 0.0),
            Key::Up => c.turn(0.0, TURN_DEG),
            Key::Down => c.turn(0.0, -TURN_DEG),
            Key::R => c.reset(),
            _ => moved = false,
        }
        changed.camera = moved;
        match key {
            Key::Equal | Key::KpAdd => c.scale_speed(2.0),
            Key::Minus | Key::KpSubtract => c.scale_speed(0.5),
            Key::RightBracket => {
                self.exposure += EXPOSURE_STEP;
                changed.exposure = true;
            }
            Key::LeftBracket => {
                self.exposure -= EXPOSURE_STEP;
                changed.exposure = true;
            }
            Key::F12 | Key::P => changed.request = Some(Request::Save),
            Key::Escape => changed.request = Some(Request::Quit),
            _ => {}
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Mat4;
    use glfw::Modifiers;

    fn controls() -> Controls {
        Controls::new(
            CameraRig::new(Mat4::IDENTITY, 40.0, (Vec3::new(0.0, 0.0, 5.0), 1.0)),
            0.0,
        )
    }

    fn press(key: Key) -> WindowEvent {
        WindowEvent::Key(key, 0, Action::Press, Modifiers::empty())
    }

    #[test]
    fn keys_move_the_camera_or_the_exposure() {
        let mut c = controls();
        let z0 = c.camera.position.z;
        let changed = c.handle(&press(Key::W));
        assert!(changed.camera && !changed.exposure);
        assert!(c.camera.position.z > z0);
        let changed = c.handle(&press(Key::RightBracket));
        assert!(!changed.camera && changed.exposure);
        assert_eq!(c.exposure, EXPOSURE_STEP);
        assert_eq!(c.handle(&press(Key::P)).request, Some(Request::Save));
        assert_eq!(c.handle(&press(Key::F12)).request, Some(Request::Save));
        assert_eq!(c.handle(&press(Key::Escape)).request, Some(Request::Quit));
        let speed = c.camera.speed;
        assert!(!c.handle(&press(Key::Equal)).camera);
        assert_eq!(c.camera.speed, 2.0 * speed);
        assert!(c.handle(&press(Key::R)).camera);
        assert_eq!(c.camera.position.z, z0);
        // Releases do nothing.
        let release = WindowEvent::Key(Key::W, 0, Action::Release, Modifiers::empty());
        assert_eq!(c.handle(&release), Changed::default());
    }

    #[test]
    fn a_drag_orbits_and_a_plain_move_does_not() {
        let mut c = controls();
        assert!(!c.handle(&WindowEvent::CursorPos(10.0, 10.0)).camera);
        c.handle(&WindowEvent::MouseButton(
            MouseButton::Button1,
            Action::Press,
            Modifiers::empty(),
        ));
        let p0 = c.camera.position;
        assert!(c.handle(&WindowEvent::CursorPos(30.0, 10.0)).camera);
        assert!((c.camera.position - p0).length() > 1e-3);
        c.handle(&WindowEvent::MouseButton(
            MouseButton::Button1,
            Action::Release,
            Modifiers::empty(),
        ));
        assert!(!c.handle(&WindowEvent::CursorPos(50.0, 10.0)).camera);
        assert!(c.handle(&WindowEvent::Scroll(0.0, 1.0)).camera);
    }
}
