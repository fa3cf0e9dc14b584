//! Headless Chromium for the page tests: where the browser is, and the flags
//! that give it a fresh, quiet, network-less profile of a fixed size.

use std::path::PathBuf;

/// Flags every page test starts the browser with (its profile directory and
/// its own flags come after them).
pub const FLAGS: [&str; 11] = [
    "--headless",
    "--no-sandbox",
    "--disable-gpu",
    "--disable-quic",
    "--no-first-run",
    "--disable-background-networking",
    "--disable-component-update",
    "--disable-sync",
    "--hide-scrollbars",
    "--force-device-scale-factor=1",
    "--window-size=1400,900",
];

/// The browser named by `LEARNPNP_CHROMIUM`, or Debian's `chromium` (or
/// `chromium-browser`) on the `PATH`.
pub fn find() -> Option<PathBuf> {
    std::env::var_os("LEARNPNP_CHROMIUM").map(PathBuf::from).or_else(|| {
        let path = std::env::var_os("PATH")?;
        std::env::split_paths(&path)
            .flat_map(|dir| ["chromium", "chromium-browser"].map(|name| dir.join(name)))
            .find(|candidate| candidate.is_file())
    })
}
