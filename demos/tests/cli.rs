//! The `tickwork` binary as a user runs it.

use std::process::Command;

fn tickwork(args: &[&str]) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_tickwork"))
        .args(args)
        .output()
        .expect("runs")
}

#[test]
fn integrators_json_lists_every_registered_method_with_its_fields() {
    let output = tickwork(&["integrators", "--json"]);
    assert!(output.status.success(), "{}", String::from_utf8_lossy(&output.stderr));
    let methods: Vec<serde_json::Value> = serde_json::from_slice(&output.stdout).expect("a JSON array");
    assert_eq!(methods.len(), tickwork_integrators::METHODS.len());
    for (json, info) in methods.iter().zip(tickwork_integrators::METHODS) {
        assert_eq!(json["name"], info.name);
        assert_eq!(json["order"], info.order);
        assert_eq!(json["order_velocity_forces"], info.order_velocity_forces);
        assert_eq!(json["evaluations"], info.evaluations);
        assert_eq!(json["symplectic"], info.symplectic);
        assert_eq!(json["reversible"], info.reversible);
        assert_eq!(json["self_starting"], info.self_starting);
        assert_eq!(json["aliases"].as_array().map(Vec::len), Some(info.aliases.len()));
    }
    let rk4 = methods.iter().find(|m| m["name"] == "rk4").expect("rk4");
    assert_eq!((rk4["order"].as_u64(), rk4["evaluations"].as_u64()), (Some(4), Some(4)));
    let leapfrog = methods.iter().find(|m| m["name"] == "leapfrog").expect("leapfrog");
    assert_eq!(leapfrog["order_velocity_forces"].as_u64(), Some(1));
    assert_eq!(leapfrog["symplectic"], true);
}

#[test]
fn integrators_table_has_a_row_per_method_and_the_angular_methods() {
    let output = tickwork(&["integrators"]);
    assert!(output.status.success());
    let text = String::from_utf8(output.stdout).expect("utf-8");
    let mut lines = text.lines();
    assert!(
        lines
            .next()
            .is_some_and(|header| header.starts_with("name") && header.contains("order x/v/drag"))
    );
    for info in tickwork_integrators::METHODS {
        assert!(
            text.lines().any(|l| l.starts_with(&format!("{} ", info.name))),
            "no row for {}",
            info.name
        );
    }
    let verlet: Vec<&str> = text
        .lines()
        .find(|l| l.starts_with("position_verlet "))
        .expect("row")
        .split_whitespace()
        .collect();
    assert_eq!(
        &verlet[..3],
        ["position_verlet", "2/1/1", "1"],
        "orders and evaluations"
    );
    assert!(text.contains("exponential_map"), "{text}");
    // No subcommand is the same listing.
    assert_eq!(tickwork(&[]).stdout, text.as_bytes());
}

#[test]
fn an_unknown_subcommand_is_an_error_naming_it() {
    let output = tickwork(&["integrater"]);
    assert!(!output.status.success());
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(stderr.contains("unrecognized subcommand 'integrater'"), "{stderr}");
    assert!(stderr.contains("integrators"), "suggests the right one: {stderr}");
}
