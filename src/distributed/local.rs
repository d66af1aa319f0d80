//! Ranks as threads of one process, joined by channels: the transport of the tests, which run
//! the same collective code paths as MPI without an MPI library.

use super::communicator::Communicator;
use super::error::DistributedError;
use std::sync::mpsc::{Receiver, Sender, channel};

/// One rank of a [`LocalWorld`].
pub struct LocalRank {
    rank: usize,
    /// `to[r]` sends to rank `r`.
    to: Vec<Sender<Vec<u8>>>,
    /// `from[r]` receives from rank `r`, in the order `r` sent (one channel per pair).
    from: Vec<Receiver<Vec<u8>>>,
}

/// A group of ranks in one process.
pub struct LocalWorld;

impl LocalWorld {
    /// Runs `body` on `size` ranks, each on a thread of its own, and returns their results in
    /// rank order. A rank that panics drops its channels, so the others get
    /// [`DistributedError::PeerLost`] at their next exchange; its own result is the panic's
    /// message as `Err`.
    pub fn run<T, F>(size: usize, body: F) -> Vec<Result<T, String>>
    where
        T: Send,
        F: Fn(LocalRank) -> T + Sync,
    {
        let mut senders: Vec<Vec<Option<Sender<Vec<u8>>>>> = (0..size).map(|_| vec![None; size]).collect();
        let mut receivers: Vec<Vec<Option<Receiver<Vec<u8>>>>> =
            (0..size).map(|_| (0..size).map(|_| None).collect()).collect();
        for from in 0..size {
            for to in 0..size {
                let (tx, rx) = channel();
                senders[from][to] = Some(tx);
                receivers[to][from] = Some(rx);
            }
        }
        let ranks: Vec<LocalRank> = senders
            .into_iter()
            .zip(receivers)
            .enumerate()
            .map(|(rank, (to, from))| LocalRank {
                rank,
                to: to.into_iter().map(|s| s.expect("every pair")).collect(),
                from: from.into_iter().map(|r| r.expect("every pair")).collect(),
            })
            .collect();
        let body = &body;
        std::thread::scope(|scope| {
            let handles: Vec<_> = ranks
                .into_iter()
                .map(|rank| scope.spawn(move || body(rank)))
                .collect();
            handles
                .into_iter()
                .map(|h| {
                    h.join().map_err(|panic| {
                        panic
                            .downcast_ref::<String>()
                            .cloned()
                            .or_else(|| panic.downcast_ref::<&str>().map(|s| s.to_string()))
                            .unwrap_or_else(|| "rank panicked".to_string())
                    })
                })
                .collect()
        })
    }
}

impl Communicator for LocalRank {
    fn rank(&self) -> usize {
        self.rank
    }

    fn size(&self) -> usize {
        self.to.len()
    }

    fn exchange(&self, outgoing: Vec<Vec<u8>>) -> Result<Vec<Vec<u8>>, DistributedError> {
        assert_eq!(outgoing.len(), self.size(), "one buffer per rank");
        for (to, bytes) in outgoing.into_iter().enumerate() {
            self.to[to]
                .send(bytes)
                .map_err(|_| DistributedError::PeerLost { rank: to })?;
        }
        self.from
            .iter()
            .enumerate()
            .map(|(rank, rx)| rx.recv().map_err(|_| DistributedError::PeerLost { rank }))
            .collect()
    }
}
