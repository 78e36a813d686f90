//! The process's allocator: mimalloc, asked for a plain block wherever a plain block is aligned
//! enough. Owns: which of mimalloc's entry points a Rust allocation takes. Must not: name
//! anything of the crate (it sits under every layer; the binary and the benchmarks install it).

use std::alloc::{GlobalAlloc, Layout};
use std::ffi::c_void;

use libmimalloc_sys as mi;

/// The alignment of every block `mi_malloc` hands out, whatever its size: its smallest block is
/// a word, and every block size a multiple of one.
const PLAIN_ALIGN: usize = std::mem::size_of::<usize>();

/// mimalloc, with an allocation that needs no more than a word's alignment served by `mi_malloc`
/// rather than `mi_malloc_aligned` (which `mimalloc::MiMalloc` calls for every allocation).
///
/// Why: in mimalloc 3, an aligned request whose block size is not a power of two (24, 48, 80
/// bytes...) that finds its page's free list empty does not gather the blocks freed to that page
/// since, as `mi_malloc` does; it over-allocates from a larger size instead. The page's list then
/// stays empty, so every later request of that size takes the slow path and is served a block
/// never used before, a cache line cold. Counted on the paper's request: about half of all
/// allocations took that path (BENCHMARKS.md, "twenty-third sitting").
pub struct Allocator;

/// Whether `mi_malloc` of the layout's size is aligned enough for it. As the standard library's
/// `System` asks of `malloc`, the alignment must also not exceed the size.
fn plain(layout: &Layout) -> bool {
    layout.align() <= PLAIN_ALIGN && layout.align() <= layout.size()
}

// SAFETY: every block comes from mimalloc and goes back to it through `mi_free` or a realloc,
// which accept blocks from any of its entry points; a plain block is used only where its
// alignment (`PLAIN_ALIGN`) satisfies the layout's.
unsafe impl GlobalAlloc for Allocator {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        let block = if plain(&layout) {
            unsafe { mi::mi_malloc(layout.size()) }
        } else {
            unsafe { mi::mi_malloc_aligned(layout.size(), layout.align()) }
        };
        block.cast()
    }

    unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
        let block = if plain(&layout) {
            unsafe { mi::mi_zalloc(layout.size()) }
        } else {
            unsafe { mi::mi_zalloc_aligned(layout.size(), layout.align()) }
        };
        block.cast()
    }

    unsafe fn dealloc(&self, ptr: *mut u8, _layout: Layout) {
        unsafe { mi::mi_free(ptr.cast::<c_void>()) }
    }

    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        // The new block must suit the old alignment at the new size.
        let plain_after = layout.align() <= PLAIN_ALIGN && layout.align() <= new_size;
        let block = if plain_after {
            unsafe { mi::mi_realloc(ptr.cast::<c_void>(), new_size) }
        } else {
            unsafe { mi::mi_realloc_aligned(ptr.cast::<c_void>(), new_size, layout.align()) }
        };
        block.cast()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Writes 0, 1, 2... into a block's first `size` bytes.
    unsafe fn fill(block: *mut u8, size: usize) {
        for i in 0..size {
            unsafe { *block.add(i) = i as u8 };
        }
    }

    /// Every layout, plain or not, gets a block aligned as it asks (zeroed when asked), which
    /// keeps its bytes through a realloc to a larger and to a smaller size.
    #[test]
    fn blocks_are_aligned_as_asked_and_keep_their_bytes_through_realloc() {
        for align in [1usize, 2, 4, 8, 16, 32, 64, 4096] {
            for size in [1usize, 3, 4, 7, 8, 12, 24, 40, 48, 80, 200, 1000, 5000, 70_000] {
                let layout = Layout::from_size_align(size, align).unwrap();
                unsafe {
                    let zeroed = Allocator.alloc_zeroed(layout);
                    assert_eq!(zeroed as usize % align, 0, "zeroed {size} at {align}");
                    assert!((0..size).all(|i| *zeroed.add(i) == 0), "zeroed {size} at {align}");
                    Allocator.dealloc(zeroed, layout);
                    for new_size in [size * 3, size.div_ceil(2)] {
                        let block = Allocator.alloc(layout);
                        assert_eq!(block as usize % align, 0, "{size} at {align}");
                        fill(block, size);
                        let moved = Allocator.realloc(block, layout, new_size);
                        assert_eq!(moved as usize % align, 0, "{size} -> {new_size} at {align}");
                        let kept = size.min(new_size);
                        assert!(
                            (0..kept).all(|i| *moved.add(i) == i as u8),
                            "{size} -> {new_size} at {align}"
                        );
                        Allocator.dealloc(moved, Layout::from_size_align(new_size, align).unwrap());
                    }
                }
            }
        }
    }
}
