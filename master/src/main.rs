//! `master`: the command line of the fmi_master crate (cli.rs).

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    std::process::exit(fmi_master::cli::main(&args));
}
