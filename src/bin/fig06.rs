//! Paper figure 6, the main job: 40 rotations of coupled wear of the standard slider-crank;
//! prints the deepest wear peaks. See `jointwear::paper::figures::wear_profiles::fig06`.
fn main() {
    jointwear::paper::figures::figure_main("fig06");
}
