//! The exact Euclidean distance transform of a cell set on the base grid.

/// Distance (m) from every cell centre to the nearest cell centre of `set` on a
/// `width × height` grid of cell size `resolution`; `INFINITY` everywhere if `set` is empty.
/// Exact Euclidean distance transform (Felzenszwalb and Huttenlocher 2012): the squared
/// transform along columns, then along rows.
pub(crate) fn distance_field(
    set: &[usize],
    width: usize,
    height: usize,
    resolution: f64,
) -> Vec<f64> {
    if set.is_empty() {
        return vec![f64::INFINITY; width * height];
    }
    const FAR: f64 = 1e30;
    let mut sq = vec![FAR; width * height];
    for &c in set {
        sq[c] = 0.0;
    }
    let n = width.max(height);
    let (mut f, mut d) = (vec![0.0; n], vec![0.0; n]);
    let (mut v, mut z) = (vec![0usize; n], vec![0.0; n + 1]);
    for i in 0..width {
        for j in 0..height {
            f[j] = sq[j * width + i];
        }
        transform_1d(&f[..height], &mut d[..height], &mut v, &mut z);
        for j in 0..height {
            sq[j * width + i] = d[j];
        }
    }
    for j in 0..height {
        f[..width].copy_from_slice(&sq[j * width..(j + 1) * width]);
        transform_1d(&f[..width], &mut d[..width], &mut v, &mut z);
        sq[j * width..(j + 1) * width].copy_from_slice(&d[..width]);
    }
    sq.iter()
        .map(|&s| {
            if s >= FAR {
                f64::INFINITY
            } else {
                s.sqrt() * resolution
            }
        })
        .collect()
}

/// The 1D squared distance transform `d[q] = min_p (q − p)² + f[p]` (lower envelope of
/// parabolas).
fn transform_1d(f: &[f64], d: &mut [f64], v: &mut [usize], z: &mut [f64]) {
    let n = f.len();
    if n == 0 {
        return;
    }
    let mut k = 0usize;
    v[0] = 0;
    z[0] = f64::NEG_INFINITY;
    z[1] = f64::INFINITY;
    for q in 1..n {
        let s = |p: usize| {
            ((f[q] + (q * q) as f64) - (f[p] + (p * p) as f64)) / (2.0 * q as f64 - 2.0 * p as f64)
        };
        let mut x = s(v[k]);
        while x <= z[k] {
            k -= 1;
            x = s(v[k]);
        }
        k += 1;
        v[k] = q;
        z[k] = x;
        z[k + 1] = f64::INFINITY;
    }
    k = 0;
    for (q, out) in d.iter_mut().enumerate() {
        while z[k + 1] < q as f64 {
            k += 1;
        }
        let p = v[k];
        *out = (q as f64 - p as f64).powi(2) + f[p];
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The transform equals the brute-force minimum over the set.
    #[test]
    fn distance_field_matches_brute_force() {
        let (w, h, res) = (23, 17, 0.05);
        for set in [
            vec![0],
            vec![w * h - 1],
            vec![5 * w + 7, 12 * w + 20, 3],
            (0..w * h).filter(|c| c % 29 == 3).collect::<Vec<_>>(),
        ] {
            let field = distance_field(&set, w, h, res);
            for (c, d) in field.iter().enumerate() {
                let (i, j) = ((c % w) as f64, (c / w) as f64);
                let brute = set
                    .iter()
                    .map(|&s| {
                        let (si, sj) = ((s % w) as f64, (s / w) as f64);
                        (i - si).hypot(j - sj) * res
                    })
                    .fold(f64::INFINITY, f64::min);
                assert!((d - brute).abs() < 1e-9, "cell {c}: {d} vs {brute}");
            }
        }
        assert!(
            distance_field(&[], 4, 3, res)
                .iter()
                .all(|d| d.is_infinite())
        );
    }
}
