//! The window of the live display (cargo feature `display`): a minifb
//! window (X11, loaded at run time) showing each [`PartialFrame`].

use std::time::Duration;

use super::{FrameObserver, PartialFrame};

/// A window of one image size.
pub struct Window {
    inner: minifb::Window,
    buffer: Vec<u32>,
    size: (u32, u32),
}

impl Window {
    /// Opens a window for `width` x `height` images; fails without a
    /// display.
    pub fn open(width: u32, height: u32) -> Result<Window, String> {
        let inner = minifb::Window::new(
            "plytrace",
            width as usize,
            height as usize,
            minifb::WindowOptions::default(),
        )
        .map_err(|e| e.to_string())?;
        Ok(Window {
            inner,
            buffer: vec![0; width as usize * height as usize],
            size: (width, height),
        })
    }

    /// The image size.
    pub fn size(&self) -> (u32, u32) {
        self.size
    }

    /// Whether the user has not closed it.
    pub fn is_open(&self) -> bool {
        self.inner.is_open()
    }

    /// Waits until a key is pressed in the window or it is closed.
    pub fn wait_key(&mut self) {
        while self.inner.is_open() {
            if !self
                .inner
                .get_keys_pressed(minifb::KeyRepeat::No)
                .is_empty()
            {
                return;
            }
            self.inner.update();
            std::thread::sleep(Duration::from_millis(16));
        }
    }
}

/// A colour channel, 0 to 1, as a byte.
fn byte(c: f32) -> u32 {
    (c.clamp(0.0, 1.0) * 255.0).round() as u32
}

impl FrameObserver for Window {
    fn frame(&mut self, frame: &PartialFrame<'_>) {
        let f = frame.frame;
        if (f.width, f.height) != self.size {
            return;
        }
        for (px, c) in self.buffer.iter_mut().zip(&f.color) {
            *px = (byte(c[0]) << 16) | (byte(c[1]) << 8) | byte(c[2]);
        }
        self.inner.set_title(&format!(
            "plytrace: level {} of {}",
            frame.level, frame.levels
        ));
        let (w, h) = (self.size.0 as usize, self.size.1 as usize);
        // A closed window is not an error of the render.
        let _ = self.inner.update_with_buffer(&self.buffer, w, h);
    }
}
