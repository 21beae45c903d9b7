//! The right-hand side is the hot path of every run: it must not allocate.

use jointwear::scene::scene_path;
use jointwear::simulation::Scene;
use std::alloc::{GlobalAlloc, Layout, System};
use std::sync::atomic::{AtomicUsize, Ordering};

/// Counts allocations made anywhere in this test binary.
struct Counting;

static ALLOCATIONS: AtomicUsize = AtomicUsize::new(0);

unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        ALLOCATIONS.fetch_add(1, Ordering::Relaxed);
        System.alloc(layout)
    }

    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        System.dealloc(ptr, layout)
    }
}

#[global_allocator]
static GLOBAL: Counting = Counting;

#[test]
fn rhs_does_not_allocate() {
    let scene = Scene::load(scene_path("standard")).unwrap();
    let m = &scene.mechanism;
    let (state, mut ws) = (m.initial_state(), m.workspace());
    let mut y = m.assemble(&scene.guess).unwrap();
    let n = m.coordinates();
    // Move the bearing's body so that the journal presses on it: contact forces included.
    let cj = &m.clearance_joints[0];
    let (c, bearing) = (cj.clearance(), cj.bearing.body.unwrap());
    y[3 * bearing] -= c + 1e-6;
    assert!(m.contact_state(&state, 0, &y[..n], &y[n..2 * n]).f_n > 0.0);
    let mut dy = vec![0.0; y.len()];
    // The run's right-hand side (joint coordinates for this tree) and the absolute one; the
    // former at t = 0, where its prescribed crank is where y has it.
    let z = m.ode_state(&y);
    let mut dz = vec![0.0; z.len()];
    let before = ALLOCATIONS.load(Ordering::Relaxed);
    for i in 0..100 {
        m.rhs(&state, &mut ws, 1e-5 * i as f64, &y, &mut dy)
            .unwrap();
        m.ode_rhs(&state, &mut ws, 0.0, &z, &mut dz).unwrap();
    }
    assert_eq!(ALLOCATIONS.load(Ordering::Relaxed) - before, 0);
    assert!(
        ws.last_gaps()[0].value > 0.0,
        "the joint coordinates' state is in contact"
    );
}
