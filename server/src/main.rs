//! `nhlab`: serves the API and the page on `--addr` (or `NHLAB_ADDR`, default
//! 127.0.0.1:8080) until Ctrl-C or SIGTERM.

use clap::Parser;
use nhlab_server::{AppState, Config, app};
use std::io::IsTerminal;
use std::time::Duration;
use tokio::sync::watch;
use tracing_subscriber::EnvFilter;

/// How long open requests may take to finish after a shutdown signal.
const GRACE: Duration = Duration::from_secs(10);

/// nhlab: long-time behaviour of nonholonomic integrators, as a web service.
#[derive(Debug, Parser)]
#[command(version, about)]
struct Args {
    /// Address to listen on, HOST:PORT.
    #[arg(long, env = "NHLAB_ADDR", default_value = "127.0.0.1:8080")]
    addr: String,
}

#[tokio::main]
async fn main() -> std::process::ExitCode {
    tracing_subscriber::fmt()
        .with_env_filter(
            EnvFilter::try_from_default_env().unwrap_or_else(|_| EnvFilter::new("info")),
        )
        .with_writer(std::io::stderr)
        .with_ansi(std::io::stderr().is_terminal())
        .init();
    let args = Args::parse();
    let listener = match tokio::net::TcpListener::bind(&args.addr).await {
        Ok(l) => l,
        Err(e) => {
            tracing::error!("cannot listen on {}: {e}", args.addr);
            return std::process::ExitCode::FAILURE;
        }
    };
    match listener.local_addr() {
        Ok(addr) => tracing::info!("nhlab listening on http://{addr}"),
        Err(e) => tracing::warn!("listening, address unknown: {e}"),
    }
    let (stop_tx, mut stop_rx) = watch::channel(false);
    let server = axum::serve(listener, app(AppState::new(Config::default())))
        .with_graceful_shutdown(async move {
            shutdown_signal().await;
            tracing::info!("shutting down: no new connections, finishing open requests");
            let _ = stop_tx.send(true);
        });
    let deadline = async move {
        let _ = stop_rx.wait_for(|&stop| stop).await;
        tokio::time::sleep(GRACE).await;
    };
    tokio::select! {
        result = server => {
            if let Err(e) = result {
                tracing::error!("server error: {e}");
                return std::process::ExitCode::FAILURE;
            }
        }
        () = deadline => tracing::warn!("requests still open after {GRACE:?}; exiting"),
    }
    std::process::ExitCode::SUCCESS
}

async fn shutdown_signal() {
    let ctrl_c = async {
        if let Err(e) = tokio::signal::ctrl_c().await {
            tracing::error!("cannot listen for Ctrl-C: {e}");
            std::future::pending::<()>().await;
        }
    };
    #[cfg(unix)]
    let terminate = async {
        match tokio::signal::unix::signal(tokio::signal::unix::SignalKind::terminate()) {
            Ok(mut s) => {
                s.recv().await;
            }
            Err(e) => {
                tracing::error!("cannot listen for SIGTERM: {e}");
                std::future::pending::<()>().await;
            }
        }
    };
    #[cfg(not(unix))]
    let terminate = std::future::pending::<()>();
    tokio::select! {
        () = ctrl_c => {}
        () = terminate => {}
    }
}
