//! The order of Gauss-Seidel, from the connection graph. An output that depends directly on
//! its component's inputs (feedthrough, from ModelStructure) is final only once those inputs
//! are, so its component steps before the components it feeds; an output with no direct
//! dependency (a state) leaves the order free. The order is the topological order of those
//! constraints, ties in declaration order. A cycle through connections and direct
//! dependencies is an algebraic loop: it is reported with its variables named.
//! Uses structure.rs and error.rs.

use crate::error::{Error, Result};
use crate::structure::System;
use std::collections::{BTreeMap, BTreeSet};

/// Variables as (component, variable index).
type Var = (usize, usize);

fn name(sys: &System, (c, v): Var) -> String {
    let comp = &sys.components[c].name;
    format!("{comp}.{}", sys.md(c).variables[v].name)
}

/// The variable graph: connections output → input, and inside a component connected input →
/// output where the output depends directly on the input.
fn graph(sys: &System) -> BTreeMap<Var, Vec<Var>> {
    let mut g: BTreeMap<Var, Vec<Var>> = BTreeMap::new();
    let inputs: BTreeSet<Var> = sys.links.iter().map(|l| l.to).collect();
    let outputs: BTreeSet<Var> = sys.links.iter().map(|l| l.from).collect();
    for l in &sys.links {
        g.entry(l.from).or_default().push(l.to);
    }
    for &(c, u) in &inputs {
        for &(oc, y) in outputs.iter().filter(|(oc, _)| *oc == c) {
            if sys.md(c).feedthrough(y, u) {
                g.entry((c, u)).or_default().push((oc, y));
            }
        }
    }
    g
}

/// The first cycle of `g`, if any, as its variables in order.
fn find_cycle(g: &BTreeMap<Var, Vec<Var>>) -> Option<Vec<Var>> {
    // iterative DFS with colours: 0 new, 1 on the stack, 2 done
    let mut colour: BTreeMap<Var, u8> = BTreeMap::new();
    for &root in g.keys() {
        if colour.get(&root).copied().unwrap_or(0) != 0 {
            continue;
        }
        let mut stack: Vec<(Var, usize)> = vec![(root, 0)];
        colour.insert(root, 1);
        while let Some(&mut (node, ref mut next)) = stack.last_mut() {
            let succ = g.get(&node).map(Vec::as_slice).unwrap_or(&[]);
            if *next < succ.len() {
                let s = succ[*next];
                *next += 1;
                match colour.get(&s).copied().unwrap_or(0) {
                    0 => {
                        colour.insert(s, 1);
                        stack.push((s, 0));
                    }
                    1 => {
                        let at = stack.iter().position(|(n, _)| *n == s).unwrap_or(0);
                        return Some(stack[at..].iter().map(|(n, _)| *n).collect());
                    }
                    _ => {}
                }
            } else {
                colour.insert(node, 2);
                stack.pop();
            }
        }
    }
    None
}

/// An algebraic loop, if the system has one: an error naming its variables.
pub fn algebraic_loop(sys: &System) -> Result<()> {
    match find_cycle(&graph(sys)) {
        None => Ok(()),
        Some(cycle) => {
            let mut names: Vec<String> = cycle.iter().map(|&v| name(sys, v)).collect();
            names.push(names[0].clone());
            Err(Error::new(format!(
                "algebraic loop: {} (each output depends directly on the input before it)",
                names.join(" → ")
            )))
        }
    }
}

/// Gauss-Seidel's order of the components (indices), or the algebraic loop.
pub fn gauss_seidel(sys: &System) -> Result<Vec<usize>> {
    algebraic_loop(sys)?;
    let n = sys.components.len();
    let mut before: Vec<BTreeSet<usize>> = vec![BTreeSet::new(); n];
    let connected: BTreeSet<Var> = sys.links.iter().map(|l| l.to).collect();
    for l in &sys.links {
        let (a, y) = l.from;
        let b = l.to.0;
        let direct = connected
            .iter()
            .any(|&(c, u)| c == a && sys.md(a).feedthrough(y, u));
        if direct && a != b {
            before[b].insert(a);
        }
    }
    let mut order = Vec::with_capacity(n);
    let mut placed = vec![false; n];
    while order.len() < n {
        let ready = (0..n)
            .filter(|&c| !placed[c])
            .min_by_key(|&c| (before[c].iter().filter(|&&a| !placed[a]).count(), c));
        // some component is left while the order is short
        let Some(c) = ready else { break };
        placed[c] = true;
        order.push(c);
    }
    Ok(order)
}
