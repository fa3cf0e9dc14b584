//! The plans shipped in `plans/` are the catalogued thesis plans, and they load.
//!
//! Regenerate them after changing the catalog:
//! `LEARNPNP_WRITE_PLANS=1 cargo test --test shipped_plans`

use std::path::PathBuf;

use learnpnp::plan::{AllowedAtoms, catalog};
use learnpnp::plan_file::load_plan;
use learnpnp::pnml::{self, Dialect};

fn plans_dir() -> PathBuf {
    crate::util::root().to_path_buf().join("plans")
}

#[test]
fn shipped_files_match_the_catalog() {
    let write = std::env::var_os("LEARNPNP_WRITE_PLANS").is_some();
    for (stem, net) in catalog::all().expect("catalog builds") {
        let path = plans_dir().join(format!("{stem}.pnml"));
        if write {
            pnml::write_file(&net, Dialect::Jarp, &path).expect("write plan");
        }
        let shipped = pnml::read_file(&path).unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(
            shipped,
            net,
            "{} differs from the catalog; regenerate it",
            path.display()
        );
    }
}

#[test]
fn shipped_files_load_and_pass_the_checks() {
    for (stem, _) in catalog::all().expect("catalog builds") {
        let path = plans_dir().join(format!("{stem}.pnml"));
        let plan = load_plan(&path, AllowedAtoms::Open).unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(plan.name(), stem);
        let report = learnpnp::analysis::check(&plan, learnpnp::analysis::DEFAULT_LIMIT);
        assert!(report.passed(), "{}: {report}", path.display());
    }
}
