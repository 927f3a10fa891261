//! The run-time profile of the image generation processor, in the
//! categories of Garcia 1986, table 6.2: the major functions (Addobj,
//! Expobj, Sortply, Shadows, Shading, Misc) and the operations they use
//! (ChkBBOX, ChkPLY, Clipping, Transform). Enabled by `--profile`; when off,
//! a timer costs one branch.

use std::fmt;
use std::sync::atomic::{AtomicU64, Ordering};
use std::time::{Duration, Instant};

/// A category of table 6.2.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Category {
    /// Building each tree node's object list (culling, clipping).
    Addobj,
    /// Expanding objects into potentially visible polygons (level 1).
    Expobj,
    /// Depth sorting the polygon lists.
    Sortply,
    /// Computing shadow polygons.
    Shadows,
    /// The illumination model.
    Shading,
    /// Reading the scene, painting and writing the output.
    Misc,
    /// Bounding boxes against clipping or shadow volumes.
    ChkBbox,
    /// Polygons against shadow volumes.
    ChkPly,
    /// Clipping polygons to volumes.
    Clipping,
    /// Transforming coordinates.
    Transform,
}

const ALL: [(Category, &str); 10] = [
    (Category::Addobj, "Addobj"),
    (Category::Expobj, "Expobj"),
    (Category::Sortply, "Sortply"),
    (Category::Shadows, "Shadows"),
    (Category::Shading, "Shading"),
    (Category::Misc, "Misc"),
    (Category::ChkBbox, "ChkBBOX"),
    (Category::ChkPly, "ChkPLY"),
    (Category::Clipping, "Clipping"),
    (Category::Transform, "Transform"),
];

/// Accumulated times per category.
#[derive(Debug, Default)]
pub struct Profile {
    enabled: bool,
    /// Nanoseconds per category; atomic, so parallel work (the shadows of
    /// a level) adds its threads' times.
    times: [AtomicU64; 10],
}

impl Clone for Profile {
    fn clone(&self) -> Self {
        let p = Profile::new(self.enabled);
        for (a, b) in p.times.iter().zip(&self.times) {
            a.store(b.load(Ordering::Relaxed), Ordering::Relaxed);
        }
        p
    }
}

/// Adds the time from its creation to its drop to a category.
pub struct Timer<'a> {
    slot: Option<(&'a AtomicU64, Instant)>,
}

impl Drop for Timer<'_> {
    fn drop(&mut self) {
        if let Some((cell, start)) = self.slot {
            cell.fetch_add(nanos(start.elapsed()), Ordering::Relaxed);
        }
    }
}

impl Profile {
    /// A profile, recording only if `enabled`.
    pub fn new(enabled: bool) -> Profile {
        Profile {
            enabled,
            times: Default::default(),
        }
    }

    /// Times the rest of the enclosing scope into `category`.
    pub fn time(&self, category: Category) -> Timer<'_> {
        Timer {
            slot: self
                .enabled
                .then(|| (&self.times[category as usize], Instant::now())),
        }
    }

    /// Adds `d` to `category`.
    pub fn add(&self, category: Category, d: Duration) {
        if self.enabled {
            self.times[category as usize].fetch_add(nanos(d), Ordering::Relaxed);
        }
    }

    /// The time of `category`.
    pub fn get(&self, category: Category) -> Duration {
        Duration::from_nanos(self.times[category as usize].load(Ordering::Relaxed))
    }

    /// Whether it records.
    pub fn enabled(&self) -> bool {
        self.enabled
    }
}

fn nanos(d: Duration) -> u64 {
    u64::try_from(d.as_nanos()).unwrap_or(u64::MAX)
}

impl fmt::Display for Profile {
    /// Table 6.2's layout: the major functions as percentages of their sum
    /// (the generation time), then the operations as percentages of it.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let total: Duration = ALL[..6].iter().map(|(c, _)| self.get(*c)).sum();
        let pct = |d: Duration| {
            if total.is_zero() {
                0.0
            } else {
                100.0 * d.as_secs_f64() / total.as_secs_f64()
            }
        };
        writeln!(
            f,
            "Run-time profile (004 table 6.2), G-Time = {:.3} ms",
            total.as_secs_f64() * 1e3
        )?;
        for (i, (c, name)) in ALL.iter().enumerate() {
            if i == 6 {
                writeln!(f, "  -- used by the above --")?;
            }
            let d = self.get(*c);
            writeln!(
                f,
                "  {name:<10} {:>6.1}%  {:>10.3} ms",
                pct(d),
                d.as_secs_f64() * 1e3
            )?;
        }
        Ok(())
    }
}
