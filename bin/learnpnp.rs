//! The `learnpnp` command line.

fn main() {
    println!("learnpnp");
}
