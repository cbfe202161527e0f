//! Sharing a model between threads.

use kinscene_pinocchio::{Data, Model, forward_kinematics, frame_placement};
use nalgebra::DVector;

use crate::support::{mixed_model, mixed_q};

const fn assert_send_sync<T: Send + Sync>() {}
const fn assert_send<T: Send>() {}
const _: () = assert_send_sync::<Model>();
const _: () = assert_send::<Data>();

fn tool_translations(model: &Model, qs: &[DVector<f64>]) -> Vec<[f64; 3]> {
    let tool = model.frame_index("tool").unwrap();
    let mut data = Data::new(model).unwrap();
    qs.iter()
        .map(|q| {
            forward_kinematics(model, &mut data, q).unwrap();
            frame_placement(model, &data, tool)
                .unwrap()
                .translation
                .vector
                .into()
        })
        .collect()
}

#[test]
fn two_threads_on_one_model_agree_with_one_thread() {
    let (model, _) = mixed_model();
    let qs: Vec<_> = (0..200)
        .map(|i| {
            let t = i as f64 * 0.037;
            mixed_q(
                [t.sin(), t.cos(), 3.0 * t],
                t,
                -2.0 * t,
                0.5 * t.sin(),
                0.1 * t.cos(),
            )
        })
        .collect();
    let reference = tool_translations(&model, &qs);
    let (a, b) = std::thread::scope(|s| {
        let a = s.spawn(|| tool_translations(&model, &qs));
        let b = s.spawn(|| tool_translations(&model, &qs));
        (a.join().unwrap(), b.join().unwrap())
    });
    // Same inputs, same code: bitwise equal, whatever the interleaving.
    assert_eq!(a, reference);
    assert_eq!(b, reference);
    // The configurations really differ, so equality is not trivial.
    assert_ne!(reference[0], reference[100]);
}
