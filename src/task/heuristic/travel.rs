//! The `travel` term: the distance fields `D_j`, the set distances `d(C_i, C_k)` and the
//! minimum spanning tree over the unmet goals' sets.

use super::Heuristic;
use super::distance::distance_field;

impl Heuristic<'_> {
    /// `D_k` of goal target `k` (which has a set).
    fn field(&self, k: usize) -> &[f64] {
        self.fields[k].get_or_init(|| {
            let set = self.sets[k].as_deref().unwrap_or_default();
            distance_field(set, self.width, self.height, self.resolution)
        })
    }

    /// `d(C_i, C_k)`.
    fn pair(&self, i: usize, k: usize) -> f64 {
        let (i, k) = (i.min(k), i.max(k));
        let n = self.sets.len();
        *self.pairs[i * n + k].get_or_init(|| {
            let set = self.sets[i].as_deref().unwrap_or_default();
            let field = self.field(k);
            set.iter().map(|&c| field[c]).fold(f64::INFINITY, f64::min)
        })
    }

    /// The `travel` term of a state, as a function of the robot's cell.
    pub fn travel_of(&self, key: &[u16]) -> Travel<'_> {
        let weight = self.settings.cost.travel;
        let mut fields = Vec::new();
        let mut unmet = Vec::new();
        if weight > 0.0 {
            for (k, ((j, i), set)) in self
                .problem
                .goal
                .targets()
                .iter()
                .zip(&self.sets)
                .enumerate()
            {
                let v = self.lattice.values(*j)[key[j.index()] as usize];
                if set.as_ref().is_some_and(|s| !s.is_empty()) && !i.contains(v) {
                    unmet.push(k);
                    fields.push(self.field(k));
                }
            }
        }
        // Prim's algorithm over the unmet goals' sets.
        let mut tree = 0.0;
        if unmet.len() > 1 {
            let mut best: Vec<f64> = unmet.iter().map(|&k| self.pair(unmet[0], k)).collect();
            let mut done = vec![false; unmet.len()];
            done[0] = true;
            for _ in 1..unmet.len() {
                let (next, d) = best
                    .iter()
                    .enumerate()
                    .filter(|(a, _)| !done[*a])
                    .map(|(a, d)| (a, *d))
                    .fold(
                        (usize::MAX, f64::INFINITY),
                        |x, y| if y.1 < x.1 { y } else { x },
                    );
                if next == usize::MAX {
                    break;
                }
                done[next] = true;
                tree += d;
                for (a, b) in best.iter_mut().enumerate() {
                    if !done[a] {
                        *b = b.min(self.pair(unmet[next], unmet[a]));
                    }
                }
            }
        }
        Travel {
            weight,
            tree,
            fields,
        }
    }
}

/// The `travel` term of one state.
pub(crate) struct Travel<'h> {
    weight: f64,
    /// Minimum spanning tree weight over the unmet goals' sets (m).
    tree: f64,
    /// `D_j` of the unmet goals.
    fields: Vec<&'h [f64]>,
}

impl Travel<'_> {
    /// The term with the robot at `cell`.
    pub fn at(&self, cell: usize) -> f64 {
        if self.fields.is_empty() {
            return 0.0;
        }
        let (mut near, mut far) = (f64::INFINITY, 0.0f64);
        for f in &self.fields {
            near = near.min(f[cell]);
            far = far.max(f[cell]);
        }
        self.weight * far.max(near + self.tree)
    }
}
