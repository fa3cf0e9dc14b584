//! `learnpnp-ros2-world MAPPING`: a ROS 2 robot as a learnpnp world, over
//! rmw_zenoh's wire format (no ROS 2 installed). Started by
//! `learnpnp-supervisor --world-cmd "learnpnp-ros2-world MAPPING" --plan PLAN`;
//! the mapping file (TOML, the guide's `docs/guide/src/ros2.md`) names the router, the topics the
//! atoms and fluents read, the reward, the episode's end, the reset service
//! and the topics or ROS 2 actions the plan's actions send, and whether (and
//! under which namespace) the agents' plan state is republished from their
//! live feed.

use std::path::PathBuf;
use std::process::ExitCode;
use std::sync::Arc;

use anyhow::Context;
use clap::Parser;
use learnpnp_ros2::feed::{FeedRepublisher, PlanStateCounts};
use learnpnp_ros2::node::Node;
use learnpnp_ros2::plan_state::Republisher;
use learnpnp_ros2::world::{Counts, Ros2World};
use learnpnp_ros2::{link, mapping};
use learnpnp_system::multiprocess::host::world::{Served, WorldRun, serve};
use serde::Serialize;

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

/// The world's report: its counts, what was served (real time: the cycle
/// kept), and the plan state's counts (none when off).
#[derive(Serialize)]
struct Report {
    #[serde(flatten)]
    world: Counts,
    served: Option<Served>,
    plan_state: Option<PlanStateCounts>,
}

/// The plan state's republishing, when the mapping asks for it: a world
/// without it (no run in the environment, publishers refused) runs on.
fn plan_state(loaded: &mapping::Loaded, node: &Node) -> Option<FeedRepublisher> {
    let section = &loaded.mapping.plan_state;
    if !section.publish {
        return None;
    }
    let started = WorldRun::from_env().map_err(anyhow::Error::from).and_then(|run| {
        let republisher = Republisher::new(node, &section.namespace, run.agents)?;
        Ok(FeedRepublisher::start(run, republisher)?)
    });
    match started {
        Ok(republisher) => Some(republisher),
        Err(e) => {
            eprintln!("learnpnp-ros2-world: no plan state: {e:#}");
            None
        }
    }
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
    let republisher = plan_state(&loaded, &node);
    let mut world = Ros2World::new(loaded, node)?;
    let served = serve(&mut world);
    let counts = Report {
        world: world.counts(),
        served: served.as_ref().ok().copied(),
        plan_state: republisher.map(FeedRepublisher::stop),
    };
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
