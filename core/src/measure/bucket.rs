//! Downsampling of an error series into [`Bucket`]s, streamed as they complete.
//!
//! A series of `total` samples becomes `min(points, total)` buckets of contiguous samples,
//! as equal in size as possible (bucket `j` ends at sample `⌊(j+1)·total/B⌋`, so sizes differ
//! by at most one). Each bucket reports its last sample's time and the mean and max of the
//! error over its samples. Memory is O(1) per series whatever the number of steps.
//!
//! The last bucket is released only by [`Bucketer::finish`], so a series whose sample count
//! was predicted rather than known (the latitude's section crossings) still closes cleanly:
//! surplus samples join the last bucket, a shortfall leaves the last bucket short.

/// One downsampled point of an error series.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Bucket {
    /// Time of the bucket's last sample.
    pub t: f64,
    /// Mean error over the bucket.
    pub mean: f64,
    /// Max error over the bucket.
    pub max: f64,
}

/// Streams samples into buckets.
#[derive(Debug, Clone)]
pub struct Bucketer(Lanes<1>);

impl Bucketer {
    /// Plans `min(points, total)` buckets (at least one) for `total` samples.
    pub fn new(total: u64, points: usize) -> Self {
        Self(Lanes::new(total, points))
    }

    /// Adds a sample; returns the bucket it completed, if any (never the last one).
    #[inline]
    pub fn push(&mut self, t: f64, error: f64) -> Option<Bucket> {
        self.0.push(t, [error]).map(|[b]| b)
    }

    /// Releases the last bucket (with any samples beyond the plan), if it has samples.
    pub fn finish(&mut self) -> Option<Bucket> {
        self.0.finish().map(|[b]| b)
    }
}

/// `K` series sampled at the same times, bucketed together: one schedule, `K` sums and
/// maxima (a run's step integrals, which share every sample time).
#[derive(Debug, Clone)]
pub struct Lanes<const K: usize> {
    total: u64,
    buckets: u64,
    index: u64,
    seen: u64,
    end: u64,
    count: u64,
    sum: [f64; K],
    max: [f64; K],
    t: f64,
}

impl<const K: usize> Lanes<K> {
    /// Plans `min(points, total)` buckets (at least one) for `total` samples.
    pub fn new(total: u64, points: usize) -> Self {
        let total = total.max(1);
        let buckets = (points.max(1) as u64).min(total);
        Self {
            total,
            buckets,
            index: 0,
            seen: 0,
            end: total / buckets,
            count: 0,
            sum: [0.0; K],
            max: [0.0; K],
            t: 0.0,
        }
    }

    /// Adds one sample to every lane; returns the buckets it completed, if any (never the
    /// last ones).
    #[inline]
    pub fn push(&mut self, t: f64, errors: [f64; K]) -> Option<[Bucket; K]> {
        self.seen += 1;
        self.count += 1;
        for (k, &e) in errors.iter().enumerate() {
            self.sum[k] += e;
            // NaN-propagating max: a NaN must show, not vanish.
            if e > self.max[k] || e.is_nan() {
                self.max[k] = e;
            }
        }
        self.t = t;
        if self.seen == self.end && self.index + 1 < self.buckets {
            let b = self.take();
            self.index += 1;
            self.end = (self.index + 1) * self.total / self.buckets;
            return Some(b);
        }
        None
    }

    /// Releases the last buckets (with any samples beyond the plan), if they have samples.
    pub fn finish(&mut self) -> Option<[Bucket; K]> {
        (self.count > 0).then(|| self.take())
    }

    fn take(&mut self) -> [Bucket; K] {
        let n = self.count as f64;
        let b =
            std::array::from_fn(|k| Bucket { t: self.t, mean: self.sum[k] / n, max: self.max[k] });
        self.count = 0;
        self.sum = [0.0; K];
        self.max = [0.0; K];
        b
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sizes(total: u64, points: usize) -> Vec<u64> {
        let mut b = Bucketer::new(total, points);
        let mut out = Vec::new();
        let mut last = 0;
        for i in 1..=total {
            if let Some(bk) = b.push(i as f64, 1.0) {
                out.push(bk.t as u64 - last);
                last = bk.t as u64;
            }
        }
        if let Some(bk) = b.finish() {
            out.push(bk.t as u64 - last);
        }
        out
    }

    #[test]
    fn sizes_are_balanced_and_cover_everything() {
        for (total, points) in
            [(30_000, 1000), (318, 1000), (318, 100), (7, 3), (1, 5), (1001, 1000)]
        {
            let s = sizes(total, points);
            assert_eq!(s.len() as u64, total.min(points as u64), "{total} {points}");
            assert_eq!(s.iter().sum::<u64>(), total);
            let (lo, hi) = (s.iter().min().unwrap(), s.iter().max().unwrap());
            assert!(hi - lo <= 1, "{total} {points}: {lo}..{hi}");
        }
    }

    #[test]
    fn mean_and_max() {
        let mut b = Bucketer::new(4, 2);
        assert_eq!(b.push(1.0, 1.0), None);
        assert_eq!(b.push(2.0, 3.0), Some(Bucket { t: 2.0, mean: 2.0, max: 3.0 }));
        assert_eq!(b.push(3.0, 5.0), None);
        assert_eq!(b.push(4.0, 1.0), None);
        assert_eq!(b.finish(), Some(Bucket { t: 4.0, mean: 3.0, max: 5.0 }));
        assert_eq!(b.finish(), None);
    }

    #[test]
    fn lanes_share_the_schedule_and_keep_their_own_sums() {
        let mut lanes = Lanes::<2>::new(4, 2);
        let mut one = Bucketer::new(4, 2);
        for (i, (a, b)) in
            [(1.0, 10.0), (3.0, f64::NAN), (5.0, 30.0), (1.0, 10.0)].iter().enumerate()
        {
            let t = (i + 1) as f64;
            let got = lanes.push(t, [*a, *b]);
            assert_eq!(got.map(|[x, _]| x), one.push(t, *a));
            if let Some([_, y]) = got {
                assert!(y.mean.is_nan() && y.max.is_nan(), "a NaN shows in mean and max");
            }
        }
        let [x, y] = lanes.finish().unwrap();
        assert_eq!(x, Bucket { t: 4.0, mean: 3.0, max: 5.0 });
        assert_eq!(y, Bucket { t: 4.0, mean: 20.0, max: 30.0 });
    }
}
