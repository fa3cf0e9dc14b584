//! `learnpnp-ros2-world MAPPING`: a ROS 2 robot as a learnpnp world, over
//! rmw_zenoh's wire format (no ROS 2 installed). Started by
//! `learnpnp-supervisor --world-cmd "learnpnp-ros2-world MAPPING" --plan PLAN`;
//! the mapping file (TOML, `docs/ROS2.md`) names the router, the topics the
//! atoms and fluents read, the reward, the episode's end, the reset service
//! and the topics or ROS 2 actions the plan's actions send.

use std::path::PathBuf;
use std::process::ExitCode;
use std::sync::Arc;

use anyhow::Context;
use clap::Parser;
use learnpnp_ros2::node::Node;
use learnpnp_ros2::world::Ros2World;
use learnpnp_ros2::{link, mapping};
use learnpnp_system::multiprocess::world_host::serve;

/// A ROS 2 robot as a learnpnp world.
#[derive(Parser)]
#[command(name = "learnpnp-ros2-world", version)]
struct Args {
    /// The mapping file (TOML).
    mapping: PathBuf,
    /// Write what was refused, timed out and counted to this JSON file at the end.
    #[arg(long)]
    report: Option<PathBuf>,
}

fn run() -> anyhow::Result<()> {
    let args = Args::parse();
    let loaded = mapping::load(&args.mapping)?;
    // The secure link's own configuration (learnpnp_bridge::link):
    // multicast scouting and gossip off, explicit endpoints, mutual TLS over
    // QUIC with the run's certificates when `tls` names their directory.
    let session = link::open(&loaded.mapping.zenoh, &loaded.dir).context("opening the zenoh session")?;
    let ros = loaded.mapping.ros.clone();
    let node = Node::new(
        session,
        Arc::new(loaded.registry.clone()),
        ros.domain,
        &ros.namespace,
        &ros.node,
    )?;
    let mut world = Ros2World::new(loaded, node)?;
    let served = serve(&mut world);
    let counts = world.counts();
    eprintln!("learnpnp-ros2-world: {}", serde_json::to_string(&counts)?);
    if let Some(path) = &args.report {
        std::fs::write(path, serde_json::to_string_pretty(&counts)?)
            .with_context(|| format!("writing {}", path.display()))?;
    }
    served?;
    Ok(())
}

fn main() -> ExitCode {
    match run() {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: learnpnp-ros2-world: {e:#}");
            ExitCode::FAILURE
        }
    }
}
