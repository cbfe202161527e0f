//! The focal open list of a search pass (A*ε) and the items it holds: unchecked moves and
//! checked moves' target states.

use std::cmp::Ordering;
use std::collections::{BTreeSet, HashMap};

use super::pass::Node;
use crate::scene::JointId;

/// What a heap item carries.
pub(super) enum Item {
    /// A move out of closed node `from`, not yet checked. `bounded`: its priority already
    /// includes the bound of [`Checker::move_bound`](crate::task::check::Checker::move_bound).
    Edge {
        from: usize,
        joint: JointId,
        to: u16,
        bounded: bool,
    },
    /// A checked move's target state, to be closed.
    Node(Box<Node>),
}

/// An open item with its priority.
pub(super) struct Entry {
    /// Lower bound on the cost of a plan through this item (`g + h`).
    pub(super) f: f64,
    pub(super) g: f64,
    /// Goal targets still unmet after this item (the focal order's first key).
    pub(super) unmet: usize,
    pub(super) seq: u64,
    pub(super) item: Item,
}

/// An `f64` ordered by [`f64::total_cmp`].
#[derive(Debug, Clone, Copy)]
struct Ordered(f64);

impl PartialEq for Ordered {
    fn eq(&self, o: &Self) -> bool {
        self.0.total_cmp(&o.0) == Ordering::Equal
    }
}
impl Eq for Ordered {}
impl PartialOrd for Ordered {
    fn partial_cmp(&self, o: &Self) -> Option<Ordering> {
        Some(self.cmp(o))
    }
}
impl Ord for Ordered {
    fn cmp(&self, o: &Self) -> Ordering {
        self.0.total_cmp(&o.0)
    }
}

/// The open list of a focal search (A*ε, Pearl and Kim 1982): the items whose `f` is within
/// the factor `weight` of the least open `f` form the *focal* set, and the search pops the
/// focal item with the fewest unmet goal targets (then lowest `f`, deepest, oldest). With
/// `weight = 1` the focal set holds only the items of least `f`: A* with ties broken by
/// progress.
pub(super) struct Open {
    weight: f64,
    /// Items with `f` at or above this are dropped (the anytime pass's incumbent cost).
    cap: f64,
    items: HashMap<u64, Entry>,
    by_f: BTreeSet<(Ordered, u64)>,
    /// Focal order: unmet targets, f, −g, seq.
    focal: BTreeSet<(usize, Ordered, Ordered, u64)>,
    /// `weight · (least open f)`: the focal set is every item with `f <= bound`.
    bound: f64,
}

impl Open {
    pub(super) fn new(weight: f64, cap: f64) -> Self {
        Open {
            weight,
            cap,
            items: HashMap::new(),
            by_f: BTreeSet::new(),
            focal: BTreeSet::new(),
            bound: f64::NEG_INFINITY,
        }
    }

    fn focal_key(e: &Entry) -> (usize, Ordered, Ordered, u64) {
        (e.unmet, Ordered(e.f), Ordered(-e.g), e.seq)
    }

    /// The focal bound for least open `f` `f_min` (a small absolute slack keeps items of
    /// equal `f` up to rounding together).
    fn bound_for(&self, f_min: f64) -> f64 {
        self.weight * f_min + 1e-9
    }

    /// Moves items into or out of the focal set after the least open `f` changed.
    fn rebound(&mut self) {
        let new = match self.by_f.first() {
            Some((f, _)) => self.bound_for(f.0),
            None => f64::NEG_INFINITY,
        };
        let old = self.bound;
        if new > old {
            let range = (
                std::ops::Bound::Excluded((Ordered(old), u64::MAX)),
                std::ops::Bound::Included((Ordered(new), u64::MAX)),
            );
            for (_, seq) in self.by_f.range(range) {
                let e = &self.items[seq];
                self.focal.insert(Self::focal_key(e));
            }
        } else if new < old {
            let range = (
                std::ops::Bound::Excluded((Ordered(new), u64::MAX)),
                std::ops::Bound::Included((Ordered(old), u64::MAX)),
            );
            for (_, seq) in self.by_f.range(range) {
                let e = &self.items[seq];
                self.focal.remove(&Self::focal_key(e));
            }
        }
        self.bound = new;
    }

    pub(super) fn push(&mut self, e: Entry) {
        // No plan through it can beat the incumbent.
        if e.f >= self.cap - 1e-9 {
            return;
        }
        let seq = e.seq;
        self.by_f.insert((Ordered(e.f), seq));
        if e.f <= self.bound {
            self.focal.insert(Self::focal_key(&e));
        }
        self.items.insert(seq, e);
        // A new least `f` lowers the bound (or sets the first one).
        if self.by_f.first().is_some_and(|(_, s)| *s == seq) {
            self.rebound();
        }
    }

    pub(super) fn pop(&mut self) -> Option<Entry> {
        let key = *self.focal.first()?;
        self.focal.remove(&key);
        let e = self
            .items
            .remove(&key.3)
            .expect("a focal item is an open item");
        self.by_f.remove(&(Ordered(e.f), e.seq));
        self.rebound();
        Some(e)
    }

    /// The least open `f` (`+∞` when empty).
    pub(super) fn least_f(&self) -> f64 {
        self.by_f.first().map_or(f64::INFINITY, |(f, _)| f.0)
    }

    /// The next `n` items in pop order (without popping them).
    pub(super) fn peek(&self, n: usize) -> impl Iterator<Item = &Entry> {
        self.focal.iter().take(n).map(|k| &self.items[&k.3])
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn entry(f: f64, g: f64, unmet: usize, seq: u64) -> Entry {
        Entry {
            f,
            g,
            unmet,
            seq,
            item: Item::Edge {
                from: 0,
                joint: JointId(0),
                to: 0,
                bounded: false,
            },
        }
    }

    /// The focal open list pops exactly what its definition says, against a brute-force
    /// scan of the open items: among those with `f <= w · (least f) + 1e-9`, the least by
    /// (unmet, f, −g, seq) (with `w = 1`: the least `f`, as A*).
    #[test]
    fn focal_open_list_matches_its_definition() {
        for weight in [1.0, 1.5, 2.0] {
            let mut open = Open::new(weight, f64::INFINITY);
            let mut shadow: Vec<(f64, f64, usize, u64)> = Vec::new();
            let mut state = 0x9e37_79b9_7f4a_7c15u64;
            let mut next = || {
                state ^= state << 13;
                state ^= state >> 7;
                state ^= state << 17;
                state
            };
            for seq in 0..3000u64 {
                if next() % 3 != 0 {
                    let f = (next() % 1000) as f64 / 10.0;
                    let g = (next() % 100) as f64 / 10.0;
                    let unmet = (next() % 6) as usize;
                    open.push(entry(f, g, unmet, seq));
                    shadow.push((f, g, unmet, seq));
                    continue;
                }
                let popped = open.pop();
                let least = shadow.iter().map(|e| e.0).fold(f64::INFINITY, f64::min);
                let expected = shadow
                    .iter()
                    .filter(|e| e.0 <= weight * least + 1e-9)
                    .min_by(|a, b| {
                        a.2.cmp(&b.2)
                            .then(a.0.total_cmp(&b.0))
                            .then((-a.1).total_cmp(&-b.1))
                            .then(a.3.cmp(&b.3))
                    })
                    .copied();
                match (popped, expected) {
                    (None, None) => {}
                    (Some(p), Some(e)) => {
                        assert_eq!(p.seq, e.3, "weight {weight}: popped {} expected {e:?}", p.f);
                        shadow.retain(|s| s.3 != e.3);
                    }
                    (p, e) => panic!("popped {:?}, expected {e:?}", p.map(|p| p.seq)),
                }
                let peeked: Vec<u64> = open.peek(3).map(|e| e.seq).collect();
                assert!(peeked.len() <= 3);
            }
        }
    }
}
