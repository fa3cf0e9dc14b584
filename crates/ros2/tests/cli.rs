//! `learnpnp-ros2-world` as a user runs it: a bad mapping file is refused
//! with a message naming the file, the entry and the token, before any
//! connection. (Also makes `cargo test` build the binary the Python test runs.)

use std::process::Command;

const WORLD: &str = env!("CARGO_BIN_EXE_learnpnp-ros2-world");

#[test]
fn a_bad_mapping_is_refused_naming_file_entry_and_token() {
    let dir = std::env::temp_dir().join(format!("learnpnp-ros2-cli-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let file = dir.join("bad.toml");
    std::fs::write(
        &file,
        "[zenoh]\nconnect = [\"tcp/127.0.0.1:9\"]\n\n[[atom]]\nname = \"at_end\"\ntopic = \"/at_end\"\ntype = \"std_msgs/msg/Bool\"\nfield = \"dat\"\nequals = true\n\n[[action]]\nname = \"go\"\ntopic = \"/cmd\"\ntype = \"std_msgs/msg/Int32\"\n",
    )
    .unwrap();
    let out = Command::new(WORLD).arg(&file).output().unwrap();
    std::fs::remove_dir_all(&dir).unwrap();
    assert!(!out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("bad.toml: [[atom]] 'at_end': 'dat': std_msgs/msg/Bool has no field 'dat'"),
        "{err}"
    );
}
