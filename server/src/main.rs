//! `nhlab`: serves the API and the page on `--addr` (or `NHLAB_ADDR`, default
//! 127.0.0.1:8080) until Ctrl-C or SIGTERM, with the limits of [`Config`] as flags and
//! environment variables (`nhlab --help`). `nhlab sweep` computes a sweep without a server
//! (whole or one shard), and joins shards (`nhlab sweep --merge`).
//!
//! Connections are served by [`serve`](nhlab_server::serve), with its timeouts and cap as
//! flags too.
//!
//! Shutdown: on the signal it stops accepting connections, closes idle ones and those that
//! have not sent a whole request head, ends every open stream with a `shutdown` event
//! (stopping its runs), lets JSON requests in flight finish, and exits 0 once every
//! connection is closed. If requests are still open after `--shutdown-grace` seconds it
//! exits anyway, with code 1.

use clap::Parser;
use nhlab_server::sweep::shards::{self, MergeFormat, Shard};
use nhlab_server::{AppState, Config, app, serve};
use std::io::IsTerminal;
use std::path::PathBuf;
use std::time::Duration;
use tokio::sync::watch;
use tracing_subscriber::EnvFilter;

/// nhlab: long-time behaviour of nonholonomic integrators, as a web service.
///
/// Every option can also be set by the environment variable shown.
#[derive(Debug, Parser)]
#[command(name = "nhlab", version, about)]
struct Args {
    #[command(subcommand)]
    command: Option<Command>,
    /// Address to listen on, HOST:PORT (the container sets 0.0.0.0:8080).
    #[arg(long, env = "NHLAB_ADDR", default_value = "127.0.0.1:8080")]
    addr: String,
    /// Most simulations computing at once (each /simulate or /scorecard request is one,
    /// whatever its methods; a stream holds its slot until it ends); more get 503 with
    /// Retry-After.
    /// Default: the number of cores.
    #[arg(long, env = "NHLAB_MAX_SIMULATIONS", default_value_t = defaults().max_simulations,
          value_parser = slots)]
    max_simulations: usize,
    /// Most steps (t_end / step) per run for a JSON answer.
    #[arg(long, env = "NHLAB_MAX_STEPS_JSON", default_value_t = defaults().max_steps_json)]
    max_steps_json: u64,
    /// Most steps (t_end / step) per run for a stream (Accept: text/event-stream).
    #[arg(long, env = "NHLAB_MAX_STEPS_STREAM", default_value_t = defaults().max_steps_stream)]
    max_steps_stream: u64,
    /// Most `points` (buckets) per series.
    #[arg(long, env = "NHLAB_MAX_POINTS", default_value_t = defaults().max_points)]
    max_points: u64,
    /// Most methods per request.
    #[arg(long, env = "NHLAB_MAX_METHODS", default_value_t = defaults().max_methods)]
    max_methods: usize,
    /// Most bytes one request's answer may hold (series × points × bytes per point, estimated
    /// before any work; more: 422 with the estimate).
    #[arg(long, env = "NHLAB_MAX_ANSWER_BYTES", default_value_t = defaults().max_answer_bytes)]
    max_answer_bytes: u64,
    /// Most bytes all answers in flight may hold together, those still being written to slow
    /// clients included (more: 503).
    #[arg(long, env = "NHLAB_MAX_INFLIGHT_BYTES",
          default_value_t = defaults().max_inflight_bytes)]
    max_inflight_bytes: u64,
    /// Most characters per formula of a system given as formulas.
    #[arg(long, env = "NHLAB_MAX_FORMULA_CHARS", default_value_t = defaults().formulas.formula.max_chars)]
    max_formula_chars: usize,
    /// Deepest nesting (parentheses, calls, signs, exponents) in a formula.
    #[arg(long, env = "NHLAB_MAX_FORMULA_DEPTH", default_value_t = defaults().formulas.formula.max_depth)]
    max_formula_depth: usize,
    /// Most parameters of a system given as formulas.
    #[arg(long, env = "NHLAB_MAX_FORMULA_PARAMETERS",
          default_value_t = defaults().formulas.max_parameters)]
    max_formula_parameters: usize,
    /// Largest request body, in bytes (larger: 413).
    #[arg(long, env = "NHLAB_MAX_BODY_BYTES", default_value_t = defaults().max_body_bytes)]
    max_body_bytes: usize,
    /// Origin allowed to call the API from another site's page (CORS), e.g.
    /// https://lab.example.org; repeat the flag or separate by commas; `*` for any.
    /// Default: none (CORS off).
    #[arg(long, env = "NHLAB_CORS_ORIGIN", value_delimiter = ',', value_parser = origin)]
    cors_origin: Vec<String>,
    /// Seconds that JSON requests in flight may take to finish after SIGTERM or Ctrl-C
    /// (streams end at once with a `shutdown` event); then the server exits anyway.
    #[arg(long, env = "NHLAB_SHUTDOWN_GRACE", default_value_t = 10.0,
          value_parser = grace)]
    shutdown_grace: f64,
    /// Seconds a client has to send a whole request head (also how long an idle keep-alive
    /// connection stays open); then the connection is closed.
    #[arg(long, env = "NHLAB_HEADER_TIMEOUT", default_value_t = 10.0, value_parser = timeout)]
    header_timeout: f64,
    /// Seconds a request body has to arrive once its handler reads it (later: 408).
    #[arg(long, env = "NHLAB_BODY_TIMEOUT", default_value_t = 10.0, value_parser = timeout)]
    body_timeout: f64,
    /// Seconds a response (or a stream) may go without any write progress, the client not
    /// reading, before its connection is closed (which stops the stream's runs).
    #[arg(long, env = "NHLAB_WRITE_TIMEOUT", default_value_t = 30.0, value_parser = timeout)]
    write_timeout: f64,
    /// Most connections open at once; more wait in the listen backlog until one closes.
    /// Default: 1024, or the open-file limit (ulimit -n) minus 64 if lower.
    #[arg(long, env = "NHLAB_MAX_CONNECTIONS",
          default_value_t = nhlab_server::serve::default_max_connections(),
          value_parser = connections)]
    max_connections: usize,
    /// Most cells per sweep (POST /sweep).
    #[arg(long, env = "NHLAB_MAX_SWEEP_CELLS", default_value_t = defaults().max_sweep_cells)]
    max_sweep_cells: u64,
    /// Most steps one sweep takes in all (cells × methods × steps per run).
    #[arg(long, env = "NHLAB_MAX_SWEEP_STEPS", default_value_t = defaults().max_sweep_steps)]
    max_sweep_steps: u64,
    /// Seconds (wall clock) one run may compute; a run past it ends as failed with a "time
    /// limit" error, where it stopped (like a run that diverges).
    #[arg(long, env = "NHLAB_MAX_RUN_SECONDS", default_value_t = defaults().max_run_seconds,
          value_parser = seconds)]
    max_run_seconds: f64,
    /// Seconds of CPU one request's runs may take together, estimated before any work (steps
    /// × the method's cost per step on the system: measured for the built-ins, from the
    /// compiled formulas' instructions for a system given as formulas); more: 422 with the
    /// estimate.
    #[arg(long, env = "NHLAB_MAX_REQUEST_SECONDS",
          default_value_t = defaults().max_request_seconds, value_parser = seconds)]
    max_request_seconds: f64,
    /// Most crossings of a Poincaré section kept per run (a request may ask for fewer).
    #[arg(long, env = "NHLAB_MAX_CROSSINGS", default_value_t = defaults().max_crossings)]
    max_crossings: u64,
}

#[derive(Debug, clap::Subcommand)]
enum Command {
    /// Computes a sweep (a POST /sweep body in SPEC) without a server, writing its rows as
    /// JSON lines after a header line; whole, or one shard of N (`--shard I/N`, cells c with
    /// c mod N = I). `--merge` joins shard files into POST /sweep's answer.
    ///
    /// On SLURM: `--shard $SLURM_ARRAY_TASK_ID/$SLURM_ARRAY_TASK_COUNT`; on a Kubernetes
    /// Indexed Job: `--shard $JOB_COMPLETION_INDEX/<completions>` (docs/scale-out.md).
    Sweep(SweepArgs),
}

#[derive(Debug, clap::Args)]
struct SweepArgs {
    /// The sweep: a JSON file with a POST /sweep body (`-`: standard input).
    #[arg(required_unless_present = "merge", conflicts_with = "merge")]
    spec: Option<PathBuf>,
    /// Compute only shard I of N (0 ≤ I < N).
    #[arg(long, value_name = "I/N", conflicts_with = "merge")]
    shard: Option<Shard>,
    /// Write to FILE instead of standard output.
    #[arg(long, value_name = "FILE")]
    out: Option<PathBuf>,
    /// Keep the whole cells already in --out (a shard that stopped midway) and compute the
    /// rest.
    #[arg(long, requires = "out", conflicts_with = "merge")]
    resume: bool,
    /// Join these shard files into POST /sweep's answer (every cell once, one spec).
    #[arg(long, value_name = "FILES", num_args = 1..)]
    merge: Vec<PathBuf>,
    /// What --merge writes: POST /sweep's JSON answer, or its CSV.
    #[arg(long, value_enum, default_value = "json", requires = "merge")]
    format: Format,
    /// Worker threads (default: the number of cores).
    #[arg(long)]
    threads: Option<usize>,
}

#[derive(Debug, Clone, Copy, clap::ValueEnum)]
enum Format {
    Json,
    Csv,
}

fn defaults() -> Config {
    Config::default()
}

fn origin(s: &str) -> Result<String, String> {
    let ok = s == "*"
        || ((s.starts_with("http://") || s.starts_with("https://"))
            && axum::http::HeaderValue::from_str(s).is_ok());
    if ok { Ok(s.to_owned()) } else { Err("an origin is scheme://host[:port], or *".into()) }
}

fn slots(s: &str) -> Result<usize, String> {
    match s.parse::<usize>() {
        Ok(n) if (1..=4096).contains(&n) => Ok(n),
        _ => Err("a number of simulations between 1 and 4096".into()),
    }
}

fn grace(s: &str) -> Result<f64, String> {
    match s.parse::<f64>() {
        Ok(x) if (0.0..=3600.0).contains(&x) => Ok(x),
        _ => Err("seconds between 0 and 3600".into()),
    }
}

fn timeout(s: &str) -> Result<f64, String> {
    match s.parse::<f64>() {
        Ok(x) if x > 0.0 && x <= 3600.0 => Ok(x),
        _ => Err("seconds, more than 0 and at most 3600".into()),
    }
}

fn seconds(s: &str) -> Result<f64, String> {
    match s.parse::<f64>() {
        Ok(x) if x > 0.0 && x <= 1e7 => Ok(x),
        _ => Err("seconds, more than 0 and at most 10000000".into()),
    }
}

fn connections(s: &str) -> Result<usize, String> {
    match s.parse::<usize>() {
        Ok(n) if (1..=1_000_000).contains(&n) => Ok(n),
        _ => Err("a number of connections between 1 and 1000000".into()),
    }
}

impl Args {
    fn config(&self) -> Config {
        Config {
            max_simulations: self.max_simulations,
            max_steps_json: self.max_steps_json,
            max_steps_stream: self.max_steps_stream,
            max_points: self.max_points,
            max_methods: self.max_methods,
            max_body_bytes: self.max_body_bytes,
            max_answer_bytes: self.max_answer_bytes,
            max_inflight_bytes: self.max_inflight_bytes,
            cors_origins: self.cors_origin.clone(),
            body_timeout: Duration::from_secs_f64(self.body_timeout),
            max_sweep_cells: self.max_sweep_cells,
            max_sweep_steps: self.max_sweep_steps,
            max_run_seconds: self.max_run_seconds,
            max_request_seconds: self.max_request_seconds,
            max_crossings: self.max_crossings,
            formulas: nhlab_core::CustomLimits {
                formula: nhlab_core::formula::Limits {
                    max_chars: self.max_formula_chars,
                    max_depth: self.max_formula_depth,
                    ..defaults().formulas.formula
                },
                max_parameters: self.max_formula_parameters,
                ..defaults().formulas
            },
            ..Config::default()
        }
    }

    fn serving(&self) -> serve::Options {
        serve::Options {
            header_timeout: Duration::from_secs_f64(self.header_timeout),
            write_timeout: Duration::from_secs_f64(self.write_timeout),
            max_connections: self.max_connections,
        }
    }
}

fn main() -> std::process::ExitCode {
    tracing_subscriber::fmt()
        .with_env_filter(
            EnvFilter::try_from_default_env().unwrap_or_else(|_| EnvFilter::new("info")),
        )
        .with_writer(std::io::stderr)
        .with_ansi(std::io::stderr().is_terminal())
        .init();
    let args = Args::parse();
    // Formulas that fall back to the interpreter give the same numbers, slower: said once
    // per process, now if the JIT is not built in or fails on a small formula tried here,
    // else at Cranelift's first failure. `GET /health` says it too.
    nhlab_core::formula::on_interpreter_fallback(|why| tracing::warn!("{why}"));
    if let Some(Command::Sweep(sweep)) = &args.command {
        return sweep_command(sweep);
    }
    let config = args.config();
    // The blocking pool follows the slots: every run of every admitted simulation, its
    // property measurements and the checks at once, and no more threads than that whatever
    // arrives (tokio's default is 512).
    // A sweep takes one thread per core instead of one per method.
    let cores = std::thread::available_parallelism().map_or(2, std::num::NonZeroUsize::get);
    let blocking = config
        .max_simulations
        .saturating_mul(config.max_methods.max(cores).saturating_add(2))
        .saturating_add(4);
    let runtime = tokio::runtime::Builder::new_multi_thread()
        .enable_all()
        .max_blocking_threads(blocking)
        .build();
    match runtime {
        Ok(runtime) => {
            let code = runtime.block_on(serve_until_stopped(args, config));
            // Every connection is closed; computations still going (a check whose client
            // left) have no one to answer and nothing to save: they do not hold up the exit.
            runtime.shutdown_background();
            code
        }
        Err(e) => {
            tracing::error!("cannot start the async runtime: {e}");
            std::process::ExitCode::FAILURE
        }
    }
}

/// `nhlab sweep`: computes a shard, or merges shard files.
fn sweep_command(args: &SweepArgs) -> std::process::ExitCode {
    let started = std::time::Instant::now();
    let result = if args.merge.is_empty() {
        let spec = args.spec.clone().unwrap_or_else(|| "-".into());
        let text = if spec.as_os_str() == "-" {
            std::io::read_to_string(std::io::stdin())
        } else {
            std::fs::read_to_string(&spec)
        };
        let file = spec.display().to_string();
        let threads = args.threads.unwrap_or_else(|| {
            std::thread::available_parallelism().map_or(1, std::num::NonZeroUsize::get)
        });
        let opts = shards::Options {
            shard: args.shard.unwrap_or(Shard::WHOLE),
            out: args.out.clone(),
            resume: args.resume,
            threads,
        };
        text.map_err(|source| shards::ShardError::Io { path: spec.clone(), source })
            .and_then(|text| shards::run(&text, &file, &opts))
            .map(|r| {
                let shard = opts.shard;
                tracing::info!(
                    "shard {}/{}: {} cells ({} kept from before) in {:.1} s",
                    shard.index,
                    shard.count,
                    r.cells,
                    r.kept,
                    started.elapsed().as_secs_f64()
                );
            })
    } else {
        let format = match args.format {
            Format::Json => MergeFormat::Json,
            Format::Csv => MergeFormat::Csv,
        };
        shards::merge(&args.merge, format).and_then(|text| {
            let (path, written) = match &args.out {
                Some(path) => (path.clone(), std::fs::write(path, text)),
                None => {
                    ("-".into(), std::io::Write::write_all(&mut std::io::stdout(), text.as_bytes()))
                }
            };
            written.map_err(|source| shards::ShardError::Io { path, source })
        })
    };
    match result {
        Ok(()) => std::process::ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("nhlab sweep: {e}");
            std::process::ExitCode::FAILURE
        }
    }
}

async fn serve_until_stopped(args: Args, config: Config) -> std::process::ExitCode {
    let listener = match tokio::net::TcpListener::bind(&args.addr).await {
        Ok(l) => l,
        Err(e) => {
            tracing::error!("cannot listen on {}: {e}", args.addr);
            return std::process::ExitCode::FAILURE;
        }
    };
    // Signal handlers first: a SIGINT sent right after the "listening" line must not meet
    // the default disposition, which would kill the server instead of shutting it down.
    let signals = shutdown_signal();
    match listener.local_addr() {
        Ok(addr) => tracing::info!("nhlab listening on http://{addr}"),
        Err(e) => tracing::warn!("listening, address unknown: {e}"),
    }
    let grace = Duration::from_secs_f64(args.shutdown_grace);
    let state = AppState::new(config);
    let (stop_tx, mut stop_rx) = watch::channel(false);
    let server = serve::serve(listener, app(state.clone()), args.serving(), async move {
        signals.await;
        tracing::info!("shutting down: no new connections, ending streams, finishing requests");
        state.shut_down();
        let _ = stop_tx.send(true);
    });
    let deadline = async move {
        let _ = stop_rx.wait_for(|&stop| stop).await;
        tokio::time::sleep(grace).await;
    };
    tokio::select! {
        () = server => tracing::info!("every connection closed; exiting"),
        () = deadline => {
            tracing::error!("requests still open after the grace period ({grace:?}); exiting (1)");
            // Returning would drop the runtime, which waits for blocking tasks (runs still
            // computing) without bound; the grace period is over.
            std::process::exit(1);
        }
    }
    std::process::ExitCode::SUCCESS
}

/// Registers SIGINT and SIGTERM now (tokio installs a Unix signal handler when the stream is
/// created, not when it is first polled) and resolves on the first of them.
#[cfg(unix)]
fn shutdown_signal() -> impl std::future::Future<Output = ()> {
    use tokio::signal::unix::{Signal, SignalKind, signal};
    let wait = |s: std::io::Result<Signal>, name: &'static str| async move {
        match s {
            Ok(mut s) => {
                s.recv().await;
            }
            Err(e) => {
                tracing::error!("cannot listen for {name}: {e}");
                std::future::pending::<()>().await;
            }
        }
    };
    let interrupt = wait(signal(SignalKind::interrupt()), "SIGINT");
    let terminate = wait(signal(SignalKind::terminate()), "SIGTERM");
    async move {
        tokio::select! {
            () = interrupt => {}
            () = terminate => {}
        }
    }
}

/// Ctrl-C elsewhere.
#[cfg(not(unix))]
fn shutdown_signal() -> impl std::future::Future<Output = ()> {
    async {
        if let Err(e) = tokio::signal::ctrl_c().await {
            tracing::error!("cannot listen for Ctrl-C: {e}");
            std::future::pending::<()>().await;
        }
    }
}
