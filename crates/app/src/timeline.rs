//! The timeline under every animation: play, pause, step forward and back, speed, scrub.
//! Keyboard: space plays or pauses, the left and right arrows step.
//!
//! A lesson's animation is a list of recorded frames (from the core's `Recorder`, see
//! [`Trace`](crate::trace::Trace)); the timeline only says how many of them are shown, so
//! stepping back and forth replays, never recomputes.

use egui::{Key, Ui};

/// Position and playback of an animation of `len` steps. `shown` steps are on screen
/// (0 = the start, before the first step; `len` = the end).
#[derive(Clone, Debug, PartialEq)]
pub struct Timeline {
    /// Steps shown.
    pub shown: usize,
    /// Steps in the animation.
    pub len: usize,
    /// Whether it is playing.
    pub playing: bool,
    /// Playback speed.
    pub steps_per_second: f32,
    /// Time gathered towards the next step while playing.
    elapsed: f32,
}

impl Default for Timeline {
    fn default() -> Self {
        Self {
            shown: 0,
            len: 0,
            playing: false,
            steps_per_second: 2.0,
            elapsed: 0.0,
        }
    }
}

impl Timeline {
    /// Sets a new length; keeps the position when it still fits, so an edit to the scene
    /// (which re-records the animation) does not jump back to the start.
    pub fn set_len(&mut self, len: usize) {
        self.len = len;
        self.shown = self.shown.min(len);
    }

    /// Back to the start, paused.
    pub fn rewind(&mut self) {
        self.shown = 0;
        self.playing = false;
    }

    /// One step forward (stops playing at the end).
    pub fn step_forward(&mut self) {
        self.shown = (self.shown + 1).min(self.len);
    }

    /// One step back.
    pub fn step_back(&mut self) {
        self.shown = self.shown.saturating_sub(1);
    }

    /// Plays from the start when at the end, otherwise plays or pauses.
    pub fn toggle_play(&mut self) {
        if !self.playing && self.shown >= self.len {
            self.shown = 0;
        }
        self.playing = !self.playing;
        self.elapsed = 0.0;
    }

    /// Whether every step is shown.
    pub fn at_end(&self) -> bool {
        self.shown >= self.len
    }

    /// Advances playback by `seconds`; returns whether the position changed.
    pub fn advance(&mut self, seconds: f32) -> bool {
        if !self.playing {
            return false;
        }
        self.elapsed += seconds * self.steps_per_second;
        let steps = self.elapsed.floor();
        self.elapsed -= steps;
        let before = self.shown;
        self.shown = (self.shown + steps as usize).min(self.len);
        if self.shown >= self.len {
            self.playing = false;
        }
        self.shown != before
    }

    /// Reads the keyboard (space, arrows) unless a text field has focus.
    pub fn handle_keys(&mut self, ui: &Ui) {
        if ui.ctx().egui_wants_keyboard_input() {
            return;
        }
        let (space, left, right) = ui.input(|input| {
            (
                input.key_pressed(Key::Space),
                input.key_pressed(Key::ArrowLeft),
                input.key_pressed(Key::ArrowRight),
            )
        });
        if space {
            self.toggle_play();
        }
        if left {
            self.playing = false;
            self.step_back();
        }
        if right {
            self.playing = false;
            self.step_forward();
        }
    }

    /// The timeline bar: buttons, the scrubber, the speed and the position, plus `caption`
    /// (what the current step is).
    pub fn ui(&mut self, ui: &mut Ui, caption: &str) {
        self.handle_keys(ui);
        let seconds = ui.input(|input| input.stable_dt).min(0.1);
        if self.advance(seconds) || self.playing {
            ui.ctx().request_repaint();
        }
        ui.horizontal(|ui| {
            if ui.button("|<").on_hover_text("Back to the start").clicked() {
                self.playing = false;
                self.shown = 0;
            }
            if ui
                .button("< step")
                .on_hover_text("One step back (left arrow)")
                .clicked()
            {
                self.playing = false;
                self.step_back();
            }
            let play_label = if self.playing { "pause" } else { "play" };
            if ui
                .button(play_label)
                .on_hover_text("Play or pause (space)")
                .clicked()
            {
                self.toggle_play();
            }
            if ui
                .button("step >")
                .on_hover_text("One step forward (right arrow)")
                .clicked()
            {
                self.playing = false;
                self.step_forward();
            }
            if ui.button(">|").on_hover_text("To the end").clicked() {
                self.playing = false;
                self.shown = self.len;
            }
            ui.separator();
            let len = self.len.max(1);
            ui.spacing_mut().slider_width = (ui.available_width() - 330.0).max(80.0);
            if ui
                .add(egui::Slider::new(&mut self.shown, 0..=len).show_value(false))
                .on_hover_text("Scrub")
                .changed()
            {
                self.playing = false;
                self.shown = self.shown.min(self.len);
            }
            ui.label(format!("step {} / {}", self.shown, self.len));
            ui.separator();
            ui.spacing_mut().slider_width = 70.0;
            ui.add(
                egui::Slider::new(&mut self.steps_per_second, 0.5..=30.0)
                    .logarithmic(true)
                    .suffix(" /s")
                    .fixed_decimals(1),
            )
            .on_hover_text("Playback speed (steps per second)");
        });
        ui.label(egui::RichText::new(caption).strong());
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn stepping_stays_within_the_animation() {
        let mut timeline = Timeline::default();
        timeline.set_len(3);
        timeline.step_back();
        assert_eq!(timeline.shown, 0);
        for _ in 0..5 {
            timeline.step_forward();
        }
        assert_eq!(timeline.shown, 3);
        timeline.set_len(2);
        assert_eq!(timeline.shown, 2, "a shorter animation clamps the position");
    }

    #[test]
    fn playback_advances_by_speed_and_stops_at_the_end() {
        let mut timeline = Timeline {
            steps_per_second: 4.0,
            ..Timeline::default()
        };
        timeline.set_len(5);
        timeline.toggle_play();
        assert!(!timeline.advance(0.1), "0.4 of a step: not yet");
        assert!(timeline.advance(0.2), "1.2 steps gathered");
        assert_eq!(timeline.shown, 1);
        timeline.advance(10.0);
        assert_eq!(timeline.shown, 5);
        assert!(!timeline.playing, "stops at the end");
        timeline.toggle_play();
        assert_eq!(timeline.shown, 0, "play at the end starts over");
    }
}
