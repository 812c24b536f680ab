//! The answer budget against what answers really hold. A counting allocator (this test
//! binary's global allocator) measures the heap a request takes at its peak, server and
//! client together in this process, the client dropping the answer's bytes as they arrive;
//! the budget's count for the request (its estimate, reserved at admission) must cover that
//! peak, and not by far more. Heap bytes, not RSS: what the allocator is asked for is the
//! same from run to run, where RSS depends on the allocator's arenas and the kernel
//! (`bench/memory.py` measures RSS on the release binary).
//!
//! One test function, so that nothing else allocates in this binary while it measures; and
//! on one CPU, so that a sweep has one worker and its cells complete in order (with two, a
//! worker that the machine pauses leaves the other's cells waiting for their turn beside
//! the answer's room, reserved but not yet written: a peak that depends on the scheduler).

use futures_util::StreamExt;
use nhlab_server::compute::Delivery;
use nhlab_server::request::SweepRequest;
use nhlab_server::sweep::Sweep;
use nhlab_server::sweep::answer::{AnswerBody, Encoder, Format};
use nhlab_server::sweep::csv;
use nhlab_server::views::{SweepCell, SweepResponse, SweepRow};
use nhlab_server::{Caches, Cancel, Config};
use nhlab_tests::TestServer;
use serde_json::{Value, json};
use std::alloc::{GlobalAlloc, Layout, System};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::Duration;

/// The system allocator, counting the bytes of the blocks allocated and not yet freed, and
/// their peak.
struct Counting;

static LIVE: AtomicUsize = AtomicUsize::new(0);
static PEAK: AtomicUsize = AtomicUsize::new(0);

/// What a block of `size` bytes takes from glibc's malloc: a word of header, rounded up to
/// 16 bytes, 32 at least; a large one (mapped) whole pages.
fn block(size: usize) -> usize {
    if size >= 128 * 1024 {
        (size + 16).next_multiple_of(4096)
    } else {
        (size + 8).next_multiple_of(16).max(32)
    }
}

fn grew(bytes: usize) {
    let live = LIVE.fetch_add(bytes, Ordering::SeqCst) + bytes;
    PEAK.fetch_max(live, Ordering::SeqCst);
}

fn shrank(bytes: usize) {
    LIVE.fetch_sub(bytes, Ordering::SeqCst);
}

// SAFETY: every call is passed on to the system allocator unchanged; only counters are kept.
unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        // SAFETY: the caller's guarantees, passed on.
        let p = unsafe { System.alloc(layout) };
        if !p.is_null() {
            grew(block(layout.size()));
        }
        p
    }

    unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
        // SAFETY: the caller's guarantees, passed on.
        let p = unsafe { System.alloc_zeroed(layout) };
        if !p.is_null() {
            grew(block(layout.size()));
        }
        p
    }

    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        // SAFETY: the caller's guarantees, passed on.
        unsafe { System.dealloc(ptr, layout) };
        shrank(block(layout.size()));
    }

    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        // SAFETY: the caller's guarantees, passed on.
        let p = unsafe { System.realloc(ptr, layout, new_size) };
        if !p.is_null() {
            // Counted as the block's new size (a copy's moment with both is not).
            let (old, new) = (block(layout.size()), block(new_size));
            if new >= old {
                grew(new - old);
            } else {
                shrank(old - new);
            }
        }
        p
    }
}

#[global_allocator]
static HEAP: Counting = Counting;

/// Runs this thread, and the threads it starts from now on, on one CPU (the first it may
/// use).
fn one_cpu() {
    // SAFETY: plain system calls on a set owned here.
    unsafe {
        let mut set: libc::cpu_set_t = std::mem::zeroed();
        assert_eq!(libc::sched_getaffinity(0, size_of::<libc::cpu_set_t>(), &mut set), 0);
        let first = (0..libc::CPU_SETSIZE as usize).find(|&c| libc::CPU_ISSET(c, &set));
        let mut one: libc::cpu_set_t = std::mem::zeroed();
        libc::CPU_SET(first.expect("a CPU to run on"), &mut one);
        assert_eq!(libc::sched_setaffinity(0, size_of::<libc::cpu_set_t>(), &one), 0);
    }
    assert_eq!(std::thread::available_parallelism().map(|n| n.get()).ok(), Some(1));
}

/// Heap bytes live now.
fn live() -> usize {
    LIVE.load(Ordering::SeqCst)
}

/// Starts measuring a peak from now.
fn reset_peak() -> usize {
    let now = live();
    PEAK.store(now, Ordering::SeqCst);
    now
}

/// Posts `body` to `path` asking for `accept`, reading the answer chunk by chunk and
/// dropping each: the answer's length.
async fn fetch(s: &TestServer, path: &str, accept: &str, body: &Value) -> usize {
    let response = reqwest::Client::new()
        .post(s.at(path))
        .header("accept", accept)
        .json(body)
        .send()
        .await
        .expect("request succeeds");
    assert_eq!(response.status(), 200, "{path} {body}");
    let mut chunks = response.bytes_stream();
    let mut length = 0;
    while let Some(chunk) = chunks.next().await {
        length += chunk.expect("the answer arrives").len();
    }
    length
}

const CVT: &str = "cvt_pendulum";
const FOUR: [&str; 4] = ["energy", "passenger_energy", "driver_energy", "constraint"];

/// The rotating CVT over ε × q[0], the paper's five methods, 20 steps, four integrals (the
/// latitude's axis would be computed for each cell, and kept in the server's cache).
fn sweep(cells: (usize, usize)) -> Value {
    json!({"system": CVT, "preset": "rotating", "t_end": 0.2, "step": 0.01, "integrals": FOUR,
        "axes": [{"path": "params.epsilon", "linspace": [0.1, 0.5, cells.0]},
                 {"path": "q[0]", "linspace": [0.5, 1.5, cells.1]}]})
}

/// A sweep whose rows are of every kind: runs that end, runs that fail (Newton at a long
/// step), invalid cells (a step longer than t_end), a latitude with a gap.
fn mixed_sweep() -> Value {
    json!({"system": CVT, "preset": "rotating", "t_end": 30,
        "methods": ["leapfrog", "rk4", {"id": "dla", "alpha": 0.4}, "dd"],
        "axes": [{"path": "step", "values": [0.01, 0.5, 2.0, 3.0, 40.0]},
                 {"path": "params.epsilon", "linspace": [0.0, 0.5, 4]}]})
}

/// What a checked sweep holds and what its answer takes, against their estimates: the
/// heap the checked cells hold (measured around [`Sweep::check`]) within `cells ×
/// cell_bytes`, the JSON answer's length within `answer_bytes`, each not far below it. The
/// answer is written here as the server writes it, from cells computed here, pushed last
/// first (so that each waits for its turn); it is the same text, byte for byte, as the whole
/// response serialized at once (and the CSV as `csv::write` over the rows).
fn sweep_here(name: &str, req: &Value) -> Sweep {
    let req: SweepRequest = serde_json::from_value(req.clone()).expect("a sweep request");
    let caches = Caches::default();
    let axis = |scene: &nhlab_core::Scene| caches.latitude(scene);
    let before = live();
    let sweep =
        Sweep::check(&req, &Config::default(), Delivery::Json, &axis, &|| None).expect("checks");
    let held = (live() - before) as f64;
    let cancel = Cancel::default();
    let n = sweep.cells.len();
    let cells: Vec<SweepCell> =
        (0..n).map(|c| sweep.compute(c, (&cancel, None), &axis).expect("not cancelled")).collect();
    let written = |format: Format| {
        let mut body = AnswerBody::new(&sweep.head, format, 0).expect("a head");
        let encoder = Encoder::new(&sweep.head, format);
        for cell in cells.iter().rev() {
            body.push(cell.cell, encoder.cell(cell).expect("encodes"));
        }
        body.finish(n).expect("every cell")
    };
    let (json, csv) = (written(Format::Json), written(Format::Csv));
    let rows: Vec<SweepRow> = cells.iter().flat_map(|c| c.rows.clone()).collect();
    let values = rows.iter().map(|r| serde_json::to_value(r).unwrap());
    let columns = csv::Columns::of(&sweep.head);
    assert_eq!(csv, csv::write(&columns, values).into_bytes(), "{name}");
    let whole = SweepResponse { head: sweep.head.clone(), rows };
    assert_eq!(json, serde_json::to_vec(&whole).unwrap(), "{name}");
    let text = String::from_utf8(json).unwrap();
    let (estimate, cells_estimate) =
        (sweep.answer_bytes() as f64, (n as u64 * sweep.cell_bytes()) as f64);
    eprintln!(
        "{name}: {} rows ({} failed, {} invalid, {} gaps): {:.0} bytes a row estimated, \
         {:.0} as JSON, {:.0} as CSV; {n} cells: {:.0} bytes a cell estimated, {:.0} held",
        whole.rows.len(),
        text.matches(r#""status":"failed""#).count(),
        text.matches(r#""status":"invalid""#).count(),
        text.matches(r#""since""#).count(),
        estimate / whole.rows.len() as f64,
        text.len() as f64 / whole.rows.len() as f64,
        csv.len() as f64 / whole.rows.len() as f64,
        cells_estimate / n as f64,
        held / n as f64,
    );
    if name == "mixed sweep" {
        for kind in [r#""status":"failed""#, r#""status":"invalid""#, r#""since""#] {
            assert!(text.contains(kind), "{name}: no {kind}");
        }
    }
    let text = text.len() as f64;
    assert!(text <= estimate && estimate <= 2.0 * text, "{name}: {text} bytes, {estimate} counted");
    // The head and the sweep's own fields besides the cells: a few kilobytes.
    assert!(
        held <= cells_estimate + 16384.0 && cells_estimate <= 2.0 * held,
        "{name}: cells hold {held} bytes, {cells_estimate} counted"
    );
    sweep
}

#[test]
fn the_budget_covers_what_the_largest_answers_hold_and_not_far_more() {
    one_cpu();
    // The estimates of sweeps, against the text and the cells they count.
    sweep_here("mixed sweep", &mixed_sweep());
    let plain = sweep_here("sweep", &sweep((40, 50)));
    // The whole request through the server, against the budget's count.
    let runtime = tokio::runtime::Builder::new_multi_thread().enable_all().build().unwrap();
    let scene =
        |t_end: f64| json!({"system": CVT, "preset": "rotating", "step": 0.01, "t_end": t_end});
    let wide: Vec<&str> = ["leapfrog", "dla", "dla01", "rk4"].repeat(4);
    let cases: Vec<(&str, &str, &str, Value)> = vec![
        ("sweep as JSON", "/sweep", "application/json", sweep((40, 50))),
        ("sweep as CSV", "/sweep", "text/csv", sweep((40, 50))),
        (
            "simulate, one long run",
            "/simulate",
            "application/json",
            json!({"system": CVT, "preset": "rotating", "step": 0.01, "t_end": 400,
                "points": 20000, "methods": ["leapfrog"]}),
        ),
        (
            "simulate, 16 runs",
            "/simulate",
            "application/json",
            json!({"system": CVT, "preset": "rotating", "step": 0.01, "t_end": 20,
                "points": 1000, "methods": wide}),
        ),
        (
            "scorecard, one scene",
            "/scorecard",
            "application/json",
            json!({"scenes": [scene(50.0)], "methods": wide, "points": 5000}),
        ),
        (
            "scorecard, four scenes",
            "/scorecard",
            "application/json",
            json!({"scenes": vec![scene(20.0); 4], "methods": wide, "points": 2000}),
        ),
    ];
    runtime.block_on(async {
        for (name, path, accept, body) in &cases {
            let s = TestServer::start().await;
            // Once small first: the server's threads, connections and caches are made then.
            let mut small = body.clone();
            small["points"] = json!(10);
            fetch(&s, path, accept, &small).await;
            s.wait_idle(Duration::from_secs(60)).await;
            let base = reset_peak();
            let length = fetch(&s, path, accept, body).await;
            s.wait_idle(Duration::from_secs(60)).await;
            // A sweep's answer is given room for its estimate: memory that is reserved, and
            // touched only as it is written.
            let unwritten =
                if *path == "/sweep" { plain.answer_bytes() as usize - length } else { 0 };
            let peak = PEAK.load(Ordering::SeqCst) - base - unwritten;
            let estimate = s.state.answers_peak() as usize;
            eprintln!(
                "{name}: {estimate} bytes counted, {peak} held at the peak ({:.2}), answer \
                 {length}",
                peak as f64 / estimate as f64
            );
            assert!(peak <= estimate, "{name}: {peak} bytes held, {estimate} counted");
            assert!(5 * peak >= estimate, "{name}: {peak} bytes held, {estimate} counted");
        }
    });
}
