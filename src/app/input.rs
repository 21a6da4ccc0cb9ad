//! The pointer's events paced for a slow frame. At a few frames a second (a software adapter,
//! a big grid rebuilt) the window hands egui a whole gesture at once: a press, the movement
//! and the release in one frame. egui then sees no drag at all (a press and a release in one
//! frame is never one), starts a drag late, from where the pointer was a frame ago, and ends
//! it on the frame that also moved it, before the tools applied that movement: quick drags
//! were lost and slow ones landed short. Here each press opens a frame of its own, the
//! movement after it comes in the next, and each release comes alone, after the movement
//! before it; what is held back goes into the next frame, in order. No egui state is read:
//! only the events.

use eframe::egui::{self, Event};

/// The events held back for the next frame.
#[derive(Debug, Default)]
pub struct InputPacer {
    held: Vec<Event>,
}

impl InputPacer {
    /// Takes this frame's `events` (after any held back before them) and leaves in it what
    /// egui should see now; the rest is held for the next frame. Returns whether some are
    /// held (the caller asks for another frame).
    pub fn pace(&mut self, events: &mut Vec<Event>) -> bool {
        let mut incoming = std::mem::take(&mut self.held);
        incoming.append(events);
        // What has passed this frame: a pointer event, a button event, a press.
        let (mut pointer, mut button, mut pressed) = (false, false, false);
        let mut rest = incoming.into_iter();
        for e in rest.by_ref() {
            let hold = match &e {
                // One button event a frame.
                Event::PointerButton { pressed: true, .. } => button,
                // A release alone, after the movement and press before it.
                Event::PointerButton { pressed: false, .. } => pointer,
                // No movement in a press's frame: the drag starts from the press next frame.
                Event::PointerMoved(_) => pressed,
                _ => false,
            };
            if hold {
                self.held.push(e);
                break;
            }
            match &e {
                Event::PointerButton { pressed: p, .. } => {
                    pressed |= *p;
                    button = true;
                    pointer = true;
                }
                Event::PointerMoved(_) => pointer = true,
                _ => {}
            }
            events.push(e);
        }
        self.held.extend(rest);
        !self.held.is_empty()
    }

    /// Paces `raw`'s events (eframe's `raw_input_hook`), asking `ctx` for the next frame
    /// when some are held.
    pub fn pace_raw(&mut self, ctx: &egui::Context, raw: &mut egui::RawInput) {
        if self.pace(&mut raw.events) {
            ctx.request_repaint();
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use egui::{Modifiers, PointerButton, Pos2};

    fn press(x: f32, down: bool) -> Event {
        Event::PointerButton {
            pos: Pos2::new(x, 0.0),
            button: PointerButton::Primary,
            pressed: down,
            modifiers: Modifiers::NONE,
        }
    }

    fn moved(x: f32) -> Event {
        Event::PointerMoved(Pos2::new(x, 0.0))
    }

    /// The frames egui sees for one frame's `events`, then empty frames until nothing is held.
    fn frames(events: Vec<Event>) -> Vec<Vec<Event>> {
        let mut pacer = InputPacer::default();
        let mut out = Vec::new();
        let mut now = events;
        loop {
            let held = pacer.pace(&mut now);
            out.push(std::mem::take(&mut now));
            if !held {
                return out;
            }
        }
    }

    #[test]
    fn a_gesture_in_one_frame_is_spread_over_press_movement_and_release() {
        let key = Event::Key {
            key: egui::Key::A,
            physical_key: None,
            pressed: true,
            repeat: false,
            modifiers: Modifiers::NONE,
        };
        let f = frames(vec![
            moved(0.0),
            press(0.0, true),
            moved(5.0),
            moved(40.0),
            press(40.0, false),
            key.clone(),
        ]);
        assert_eq!(
            f,
            vec![
                vec![moved(0.0), press(0.0, true)],
                vec![moved(5.0), moved(40.0)],
                vec![press(40.0, false), key],
            ]
        );
        // A click in one frame stays one (a press, then its release next frame).
        assert_eq!(
            frames(vec![press(3.0, true), press(3.0, false)]),
            vec![vec![press(3.0, true)], vec![press(3.0, false)]]
        );
        // Events of a slow drag's frames pass as they come.
        assert_eq!(
            frames(vec![moved(1.0), moved(2.0)]),
            vec![vec![moved(1.0), moved(2.0)]]
        );
        // A double click in one frame: four frames, in order.
        let f = frames(vec![
            press(1.0, true),
            press(1.0, false),
            press(1.0, true),
            press(1.0, false),
        ]);
        assert_eq!(f.concat().len(), 4);
        assert!(f.iter().all(|frame| frame.len() == 1), "{f:?}");
    }
}
