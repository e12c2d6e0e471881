//! A list of at most 16 small items kept inline: the collapse keeps a few per wide node
//! (the kids being opened, the lanes, a stack), and allocating for them cost more than the
//! rest of the collapse.

/// Up to 16 items of `T`, inline.
#[derive(Clone, Copy, Debug)]
pub(super) struct Lanes<T: Copy> {
    items: [T; 16],
    len: usize,
}

impl<T: Copy> Lanes<T> {
    /// The list holding `first`.
    pub fn new(first: T) -> Self {
        Self {
            items: [first; 16],
            len: 1,
        }
    }

    /// Appends `item`; panics past 16 items.
    #[inline(always)]
    pub fn push(&mut self, item: T) {
        self.items[self.len] = item;
        self.len += 1;
    }

    /// Removes and returns the last item.
    #[inline(always)]
    pub fn pop(&mut self) -> Option<T> {
        self.len = self.len.checked_sub(1)?;
        Some(self.items[self.len])
    }

    pub fn as_slice(&self) -> &[T] {
        &self.items[..self.len]
    }
}
