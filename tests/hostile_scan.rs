//! Ctrl-C during scan conversion: a band of many records over many rows
//! stops when a stop is requested ([`plytrace::internal::cancel`]), instead of
//! running to its end. The request is process-wide, so this file holds a
//! single test (its own process), which runs the cases one after another.

use std::sync::mpsc;
use std::time::Duration;

use plytrace::internal::raster::scan::{
    Method, Row, RowSink, ScanOptions, ScanStats, TransparencyRule, scan_convert,
};
use plytrace::internal::tree::{Record, RecordStream, Shades};

/// Far longer than a cancelled scan takes, far shorter than the whole
/// scan (minutes): a hang guard, not a measure of promptness.
const HANG_GUARD: Duration = Duration::from_secs(60);

/// `n` squares over the whole image, back to front.
fn squares(n: usize) -> RecordStream {
    RecordStream {
        records: (0..n)
            .map(|i| Record {
                level: 1,
                points: vec![[0.0, 0.0], [0.0, 1.0], [1.0, 1.0], [1.0, 0.0]],
                shades: Shades::Faceted([(i % 256) as u8, 100, 50]),
            })
            .collect(),
        background: Some([0, 0, 0]),
        front_to_back: false,
        blended: true,
    }
}

fn options(size: u32, act_lines: u32, threads: usize) -> ScanOptions {
    ScanOptions {
        width: size,
        height: size,
        method: Method::Supersample(4),
        act_lines,
        paint_background: true,
        // Donovan's rule: the painter takes a back-to-front stream at
        // every sampling.
        transparency: TransparencyRule::Donovan,
        threads,
        ids: true,
        max_overdraw: u64::MAX,
    }
}

/// Counts rows; never stops the scan itself (as a sink that does not
/// look at the request).
struct Rows(u32);

impl RowSink for Rows {
    fn row(&mut self, _row: &Row<'_>) -> plytrace::Result<()> {
        self.0 += 1;
        Ok(())
    }
}

/// Scans `stream` on a thread of its own, requests a stop after `after`,
/// and returns what the scan returned and the rows delivered, or panics
/// if it does not return within [`HANG_GUARD`].
fn scan_then_cancel(
    stream: RecordStream,
    options: ScanOptions,
    after: Duration,
) -> (plytrace::Result<ScanStats>, u32) {
    plytrace::internal::cancel::reset();
    let (send, receive) = mpsc::channel();
    std::thread::spawn(move || {
        let mut rows = Rows(0);
        let r = scan_convert(&stream, &options, &mut rows);
        let _ = send.send((r, rows.0));
    });
    std::thread::sleep(after);
    plytrace::internal::cancel::request();
    let out = receive
        .recv_timeout(HANG_GUARD)
        .expect("the scan did not stop within the hang guard after the request");
    plytrace::internal::cancel::reset();
    out
}

#[test]
fn a_stop_request_ends_scan_conversion_inside_a_band() {
    // One band of 1536 rows and 4000 full-image squares at 16 samples a
    // pixel: minutes of work in the band's record loop.
    let (r, rows) = scan_then_cancel(
        squares(4000),
        options(1536, 1536, 1),
        Duration::from_millis(500),
    );
    assert!(matches!(r, Err(plytrace::Error::Cancelled)), "{r:?}");
    assert_eq!(rows, 0, "no row of the unfinished band is delivered");

    // Two bands of 768 rows on two threads: both workers stop, and the
    // delivering thread reports the stop rather than a failed thread.
    let (r, _) = scan_then_cancel(
        squares(2000),
        options(1536, 768, 2),
        Duration::from_millis(500),
    );
    assert!(matches!(r, Err(plytrace::Error::Cancelled)), "{r:?}");

    // A request made before the scan starts stops it before any band.
    plytrace::internal::cancel::request();
    let r = scan_convert(&squares(3), &options(64, 64, 1), &mut Rows(0));
    assert!(matches!(r, Err(plytrace::Error::Cancelled)), "{r:?}");

    // With no request (it was reset) the same scan runs to its end.
    plytrace::internal::cancel::reset();
    let mut rows = Rows(0);
    let stats = scan_convert(&squares(3), &options(64, 16, 2), &mut rows).unwrap();
    assert_eq!(rows.0, 64);
    assert!(stats.pixels_written > 0);
}
