//! Tiny terminals: every view renders at 20x8 and 1x1 (and other odd
//! sizes) without panicking, and below the minimum shows a notice.

use omniad_tui::app::{App, ViewId, MIN_SIZE};
use ratatui::backend::TestBackend;
use ratatui::Terminal;

fn render(app: &App, w: u16, h: u16) -> String {
    let mut t = Terminal::new(TestBackend::new(w, h)).expect("test terminal");
    t.draw(|f| f.render_widget(app, f.area())).expect("draw");
    t.backend().to_string()
}

#[test]
fn every_view_renders_at_small_sizes_without_panicking() {
    let sizes = [
        (1, 1),
        (20, 8),
        (2, 30),
        (300, 3),
        (MIN_SIZE.0, MIN_SIZE.1),
        (41, 13),
        (60, 40),
    ];
    for view in ViewId::ALL {
        for help in [false, true] {
            for compare in [false, true] {
                let mut app = App::demo();
                app.view = view;
                app.help = help;
                app.sphere.compare = compare;
                for (w, h) in sizes {
                    render(&app, w, h);
                }
            }
        }
    }
}

#[test]
fn below_the_minimum_a_notice_is_shown() {
    let text = render(&App::demo(), 20, 8);
    assert!(text.contains("too small"), "{text}");
    let text = render(&App::demo(), MIN_SIZE.0, MIN_SIZE.1);
    assert!(!text.contains("too small"), "{text}");
}
