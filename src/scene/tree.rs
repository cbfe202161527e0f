//! Resolving parent names into a kinematic tree: unknown parents, cycles, pre-order numbering.

use std::collections::BTreeMap;

use super::Error;
use super::part::PartSpec;

/// The tree structure of a list of part specs.
pub(crate) struct Tree {
    /// Spec indices in depth-first pre-order: position `k` becomes `PartId(k)`.
    pub order: Vec<usize>,
    /// For each position, the parent's position (None: the base).
    pub parent: Vec<Option<usize>>,
    /// For each position, one past the last position of its subtree.
    pub subtree_end: Vec<usize>,
    /// For each position, its depth (1 for parts on the base).
    pub depth: Vec<usize>,
}

/// Resolves parents by name, rejects unknown parents and cycles, numbers parts in pre-order.
///
/// Part names must already be unique.
pub(crate) fn resolve(specs: &[PartSpec]) -> Result<Tree, Error> {
    let index: BTreeMap<&str, usize> = specs
        .iter()
        .enumerate()
        .map(|(k, s)| (s.name.as_str(), k))
        .collect();
    let mut parent_of = Vec::with_capacity(specs.len());
    for s in specs {
        parent_of.push(match &s.parent {
            None => None,
            Some(p) => Some(*index.get(p.as_str()).ok_or_else(|| Error::UnknownParent {
                part: s.name.clone(),
                parent: p.clone(),
            })?),
        });
    }
    find_cycle(specs, &parent_of)?;

    let mut children: Vec<Vec<usize>> = vec![Vec::new(); specs.len()];
    let mut roots = Vec::new();
    for (k, p) in parent_of.iter().enumerate() {
        match p {
            Some(p) => children[*p].push(k),
            None => roots.push(k),
        }
    }
    // Iterative pre-order DFS; siblings in insertion order.
    let n = specs.len();
    let mut tree = Tree {
        order: Vec::with_capacity(n),
        parent: vec![None; n],
        subtree_end: vec![0; n],
        depth: vec![0; n],
    };
    let mut position = vec![0usize; n];
    // Stack entries: (spec index, parent position, depth, entering?).
    let mut stack: Vec<(usize, Option<usize>, usize, bool)> =
        roots.iter().rev().map(|&r| (r, None, 1, true)).collect();
    while let Some((k, parent, depth, entering)) = stack.pop() {
        if !entering {
            tree.subtree_end[position[k]] = tree.order.len();
            continue;
        }
        let pos = tree.order.len();
        position[k] = pos;
        tree.order.push(k);
        tree.parent[pos] = parent;
        tree.depth[pos] = depth;
        stack.push((k, parent, depth, false));
        for &c in children[k].iter().rev() {
            stack.push((c, Some(pos), depth + 1, true));
        }
    }
    Ok(tree)
}

/// Fails with [`Error::Cycle`] naming the parts of the first cycle found.
fn find_cycle(specs: &[PartSpec], parent_of: &[Option<usize>]) -> Result<(), Error> {
    // 0: unvisited, 1: on the current chain, 2: known to reach the base.
    let mut mark = vec![0u8; specs.len()];
    for start in 0..specs.len() {
        let mut chain: Vec<usize> = Vec::new();
        let mut k = Some(start);
        while let Some(cur) = k {
            match mark[cur] {
                2 => break,
                1 => {
                    let from = chain.iter().position(|&c| c == cur).unwrap_or(0);
                    return Err(Error::Cycle {
                        parts: chain[from..]
                            .iter()
                            .map(|&c| specs[c].name.clone())
                            .collect(),
                    });
                }
                _ => {
                    mark[cur] = 1;
                    chain.push(cur);
                    k = parent_of[cur];
                }
            }
        }
        for c in chain {
            mark[c] = 2;
        }
    }
    Ok(())
}
