//! Proves that `integrate` performs no heap allocation.
//!
//! A counting global allocator counts allocations made by the current thread
//! while a thread-local flag is set, so the test harness's own threads do not
//! interfere.

mod common;

use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;

use common::Oscillators3;
use nalgebra::SVector;
use nh_runtime::{DormandPrince, Integrator, Rk4};

struct Counting;

thread_local! {
    static ACTIVE: Cell<bool> = const { Cell::new(false) };
    static COUNT: Cell<usize> = const { Cell::new(0) };
}

fn note_allocation() {
    if ACTIVE.try_with(Cell::get).unwrap_or(false) {
        let _ = COUNT.try_with(|c| c.set(c.get() + 1));
    }
}

// SAFETY: forwards to the system allocator unchanged; only counts calls.
unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        note_allocation();
        unsafe { System.alloc(layout) }
    }
    unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
        note_allocation();
        unsafe { System.alloc_zeroed(layout) }
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        note_allocation();
        unsafe { System.realloc(ptr, layout, new_size) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        unsafe { System.dealloc(ptr, layout) }
    }
}

#[global_allocator]
static GLOBAL: Counting = Counting;

/// Allocations made by `f` on this thread.
fn allocations_during<R>(f: impl FnOnce() -> R) -> (usize, R) {
    COUNT.with(|c| c.set(0));
    ACTIVE.with(|a| a.set(true));
    let r = f();
    ACTIVE.with(|a| a.set(false));
    (COUNT.with(Cell::get), r)
}

#[test]
fn counter_sees_allocations() {
    let (n, v) = allocations_during(|| vec![1u8; 16]);
    assert_eq!(v.len(), 16);
    assert!(n >= 1);
}

#[test]
fn integrate_does_not_allocate() {
    let x0 = SVector::<f64, 6>::from([1.0, 0.0, 0.5, 0.0, 0.0, 1.0]);

    let mut rk4 = Rk4::new(1e-3);
    let (n, out) = allocations_during(|| rk4.integrate(&Oscillators3, 0.0, x0, 5.0));
    let out = out.unwrap();
    assert!(out.stats.steps >= 5000);
    assert_eq!(n, 0, "Rk4 allocated {n} times");

    let mut dp = DormandPrince::new(1e-9, 1e-11);
    let (n, out) = allocations_during(|| dp.integrate(&Oscillators3, 0.0, x0, 5.0));
    let out = out.unwrap();
    assert!(out.stats.steps > 50);
    assert_eq!(n, 0, "DormandPrince allocated {n} times");

    // Error paths and the observer variant do not allocate either.
    let mut dp = DormandPrince::new(1e-9, 1e-11).with_max_steps(10);
    let mut seen = 0usize;
    let (n, out) = allocations_during(|| {
        dp.integrate_with_observer(&Oscillators3, 0.0, x0, 5.0, |_, _| seen += 1)
    });
    assert!(out.is_err());
    assert!(seen > 1);
    assert_eq!(n, 0, "DormandPrince error path allocated {n} times");
}
