//! Renders an SVG to PNG with resvg (the tests' renderer), to look at a picture:
//! `cargo run --example svg2png -- in.svg out.png [scale]`.
fn main() {
    let args: Vec<String> = std::env::args().collect();
    if args.len() < 3 {
        eprintln!("usage: svg2png IN.svg OUT.png [SCALE]");
        std::process::exit(2);
    }
    let scale: f32 = args.get(3).and_then(|s| s.parse().ok()).unwrap_or(1.0);
    let svg = std::fs::read_to_string(&args[1]).expect("read the SVG");
    let options = resvg::usvg::Options::default();
    let tree = resvg::usvg::Tree::from_str(&svg, &options).expect("parse the SVG");
    let size = tree.size().to_int_size().scale_by(scale).expect("a size");
    let mut pixmap = resvg::tiny_skia::Pixmap::new(size.width(), size.height()).expect("a pixmap");
    pixmap.fill(resvg::tiny_skia::Color::WHITE);
    let transform = resvg::tiny_skia::Transform::from_scale(scale, scale);
    resvg::render(&tree, transform, &mut pixmap.as_mut());
    pixmap.save_png(&args[2]).expect("write the PNG");
}
