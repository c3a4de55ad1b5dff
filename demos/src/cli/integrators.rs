//! `tickwork integrators [--json]`: the registry as a table or as JSON.

use std::io::{self, Write};

use clap::Args;
use serde::Serialize;
use tickwork_integrators::angular::ANGULAR_METHODS;
use tickwork_integrators::{METHODS, MethodInfo};

/// Options of `tickwork integrators`.
#[derive(Debug, Default, Args)]
pub struct IntegratorsArgs {
    /// Print a JSON array, one object per method, instead of a table.
    #[arg(long)]
    pub json: bool,
}

/// One method as `--json` prints it.
#[derive(Debug, Serialize)]
struct MethodRecord<'a> {
    name: &'a str,
    aliases: &'a [&'a str],
    title: &'a str,
    notes: &'a str,
    order: u32,
    order_velocity: u32,
    order_velocity_forces: u32,
    evaluations: u32,
    symplectic: bool,
    reversible: bool,
    self_starting: bool,
    implicit: bool,
    variable_cost: bool,
}

impl<'a> From<&'a MethodInfo> for MethodRecord<'a> {
    fn from(m: &'a MethodInfo) -> Self {
        Self {
            name: m.name,
            aliases: m.aliases,
            title: m.title,
            notes: m.notes,
            order: m.order,
            order_velocity: m.order_velocity,
            order_velocity_forces: m.order_velocity_forces,
            evaluations: m.evaluations,
            symplectic: m.symplectic,
            reversible: m.reversible,
            self_starting: m.self_starting,
            implicit: m.implicit,
            variable_cost: m.variable_cost,
        }
    }
}

fn yes(flag: bool) -> &'static str {
    if flag { "yes" } else { "-" }
}

/// Writes the listing to `out`.
///
/// # Errors
/// Any error writing to `out`.
pub fn run(args: &IntegratorsArgs, out: &mut dyn Write) -> io::Result<()> {
    if args.json {
        let records: Vec<MethodRecord<'_>> = METHODS.iter().map(MethodRecord::from).collect();
        serde_json::to_writer_pretty(&mut *out, &records).map_err(io::Error::other)?;
        return writeln!(out);
    }
    let headers = [
        "name",
        "order x/v/drag",
        "evals",
        "symplectic",
        "reversible",
        "self-starting",
        "implicit",
        "aliases",
        "notes",
    ];
    let rows: Vec<[String; 9]> = METHODS
        .iter()
        .map(|m| {
            [
                m.name.to_owned(),
                format!("{}/{}/{}", m.order, m.order_velocity, m.order_velocity_forces),
                format!("{}{}", m.evaluations, if m.variable_cost { "+" } else { "" }),
                yes(m.symplectic).to_owned(),
                yes(m.reversible).to_owned(),
                yes(m.self_starting).to_owned(),
                yes(m.implicit).to_owned(),
                m.aliases.join(", "),
                m.notes.to_owned(),
            ]
        })
        .collect();
    let mut widths = headers.map(str::len);
    for row in &rows {
        for (width, cell) in widths.iter_mut().zip(row) {
            *width = (*width).max(cell.len());
        }
    }
    let line = |out: &mut dyn Write, cells: &[&str]| -> io::Result<()> {
        let padded: Vec<String> = cells.iter().zip(widths).map(|(c, w)| format!("{c:<w$}")).collect();
        writeln!(out, "{}", padded.join("  ").trim_end())
    };
    line(out, &headers)?;
    line(
        out,
        &widths
            .map(|w| "-".repeat(w))
            .iter()
            .map(String::as_str)
            .collect::<Vec<_>>(),
    )?;
    for row in &rows {
        line(out, &row.iter().map(String::as_str).collect::<Vec<_>>())?;
    }
    writeln!(out)?;
    writeln!(
        out,
        "order x/v/drag: global order of positions, of velocities, and of the state under"
    )?;
    writeln!(
        out,
        "velocity-dependent forces; evals: force evaluations per step (+: varies per step)."
    )?;
    writeln!(out)?;
    writeln!(out, "Angular methods (orientation quaternions, rigid bodies):")?;
    for m in ANGULAR_METHODS {
        writeln!(
            out,
            "  {:<18} order {}  evals {}  {} (aliases: {})",
            m.name,
            m.order,
            m.evaluations,
            m.title,
            m.aliases.join(", ")
        )?;
    }
    Ok(())
}
