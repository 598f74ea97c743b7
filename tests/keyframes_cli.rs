//! `meadow keyframes`: the thesis' compression example reproduced exactly, and the export.

mod support;

#[test]
fn report_reproduces_the_thesis_example_and_export_writes_the_texture() {
    let dir = support::scratch("keyframes-cli");
    let png = dir.join("keyframes.png");
    let output = support::meadow()
        .args(["keyframes", "--poses", "1000", "--segments", "4", "--report", "--export"])
        .arg(&png)
        .output()
        .expect("run meadow");
    let stdout = String::from_utf8_lossy(&output.stdout);
    assert_eq!(output.status.code(), Some(0), "{}", support::transcript(&output));
    let thesis: Vec<&str> = stdout.lines().skip_while(|l| !l.starts_with("thesis blade")).take(6).collect();
    assert!(thesis[0].contains("32 vertices") && thesis[0].contains("15 records"), "{stdout}");
    assert!(thesis[1].contains(" 3072000 bits"), "{stdout}");
    assert!(thesis[4].contains(" 720000 bits"), "{stdout}");
    assert!(thesis[5].contains(" 180000 bits"), "{stdout}");
    assert!(stdout.contains("meadow blade: 4 segments, 10 vertices"), "{stdout}");
    assert!(stdout.contains("curve keyframes (3 control points") && stdout.contains("at 16 segments"), "{stdout}");
    let picture = image::open(&png).expect("exported PNG");
    assert_eq!((picture.width(), picture.height()), (4, 250));
}
