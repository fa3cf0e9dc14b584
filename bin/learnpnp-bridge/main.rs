//! `learnpnp-bridge`: one host's bridge of a run across hosts (started by
//! that host's `learnpnp-supervisor`, which passes every argument): it
//! carries the run's services between the host's iceoryx2 namespace and the
//! other hosts over Zenoh (TLS with mutual authentication by the run's
//! private CA, or plain TCP only when asked for by name; multicast scouting
//! off), and keeps what it moved and refused in `link.json`.

use std::path::PathBuf;
use std::process::ExitCode;

use clap::{Parser, ValueEnum};
use learnpnp_bridge::link::{Endpoints, Security};
use learnpnp_bridge::refusals::ZenohRefusals;
use learnpnp_bridge::{BridgeConfig, Side, run};
use learnpnp_flags::interrupt::Interrupt;
use learnpnp_system::hosts::certs::HostFiles;

/// Which host the bridge serves.
#[derive(Debug, Clone, Copy, ValueEnum)]
enum Host {
    /// Host A: the simulator or world; it serves the run's description.
    Host,
    /// A host of remote agents; it fetches the run's description.
    Remote,
}

/// One host's bridge of a run across hosts.
#[derive(Parser)]
#[command(name = "learnpnp-bridge", version)]
struct Args {
    /// This host's iceoryx2 prefix.
    #[arg(long)]
    ipc_prefix: String,
    /// Which host this is.
    #[arg(long, value_enum)]
    side: Host,
    /// Endpoints to listen on (quic/ADDRESS:PORT).
    #[arg(long)]
    listen: Vec<String>,
    /// Endpoints to connect to (quic/ADDRESS:PORT).
    #[arg(long)]
    connect: Vec<String>,
    /// This host's certificates: the run's CA, its certificate and key
    /// (a directory made by `learnpnp-supervisor link-certs`).
    #[arg(long, required_unless_present = "insecure_plain_tcp")]
    link_certs: Option<PathBuf>,
    /// Plain TCP (tcp/ADDRESS:PORT): no encryption, no authentication, no
    /// access control; anyone who reaches the port can take over the run.
    #[arg(long, conflicts_with = "link_certs")]
    insecure_plain_tcp: bool,
    /// The run's description: served (host A) or written once fetched.
    #[arg(long)]
    run_info: PathBuf,
    /// This host's work directory.
    #[arg(long)]
    work_dir: PathBuf,
}

fn main() -> ExitCode {
    learnpnp_system::multiprocess::start_process();
    let args = Args::parse();
    let zenoh = ZenohRefusals::default();
    if let Err(e) = zenoh.install() {
        eprintln!("error: bridge: counting zenoh's refusals: {e}");
        return ExitCode::FAILURE;
    }
    let security = match &args.link_certs {
        Some(dir) => match HostFiles::in_dir(dir) {
            Ok(files) => Security::MutualTls(files),
            Err(e) => {
                eprintln!("error: bridge: {e}");
                return ExitCode::FAILURE;
            }
        },
        None => Security::PlainTcp,
    };
    let interrupt = match Interrupt::install() {
        Ok(interrupt) => interrupt,
        Err(e) => {
            eprintln!("error: bridge: installing the signal handlers: {e}");
            return ExitCode::FAILURE;
        }
    };
    let config = BridgeConfig {
        ipc_prefix: args.ipc_prefix,
        side: match args.side {
            Host::Host => Side::Host,
            Host::Remote => Side::Remote,
        },
        endpoints: Endpoints {
            listen: args.listen,
            connect: args.connect,
        },
        security,
        run_info: args.run_info,
        work_dir: args.work_dir,
    };
    match run(&config, &zenoh, interrupt.flag()) {
        Ok(traffic) => {
            let m = traffic.messages;
            let (handshakes, denied) = zenoh.counts();
            eprintln!(
                "bridge: {} messages sent, {} received, {} refused; {} files; {handshakes} peers refused at the TLS handshake, {denied} messages denied by access control",
                m.sent,
                m.received,
                m.refused.total(),
                traffic.files
            );
            ExitCode::SUCCESS
        }
        Err(e) => {
            eprintln!("error: bridge: {e}");
            ExitCode::FAILURE
        }
    }
}
