//! Probes in the editor: the Probe tool drops one on the map (or on the ground in the 3D
//! view); each records the live wind where it stands, plotted under the map (speed and
//! direction over time, egui_plot) with its min, mean, max and gust factor, and exported as
//! CSV (`engine::probe`, as `windloom probe` writes it).

use super::{EditorApp, Sel};
use crate::doc::{self, Edit};
use crate::engine::live::Snapshot;
use crate::engine::probe::{self, Reading};
use eframe::egui::{self, Color32, RichText};
use std::collections::HashMap;

/// The plots' height, points.
const PLOT_HEIGHT: f32 = 130.0;

/// Readings kept per probe: ten minutes at 60 a second.
const KEEP: usize = 36_000;

/// The probes' records of the live wind.
#[derive(Default)]
pub struct ProbeLog {
    pub records: HashMap<u32, Vec<Reading>>,
    /// The simulation time last read (a snapshot read twice is read once).
    last_time: Option<f32>,
}

impl ProbeLog {
    /// Reads the snapshot's wind at every probe of `layout`, when it is newer than the last;
    /// a field that went back in time (Reset, a rebuilt field) starts the records anew.
    pub fn record(&mut self, layout: &doc::Layout, snap: &Snapshot) {
        if snap.nx == 0 || snap.velocity.len() != snap.nx * snap.ny {
            return;
        }
        match self.last_time {
            Some(t) if snap.time == t => return,
            Some(t) if snap.time < t => self.records.clear(),
            _ => {}
        }
        self.last_time = Some(snap.time);
        self.records
            .retain(|id, _| layout.probes.iter().any(|p| p.id == *id));
        for p in &layout.probes {
            let r = self.records.entry(p.id).or_default();
            r.push(Reading {
                time: snap.time,
                wind: snap.sample(p.pos),
            });
            if r.len() > KEEP {
                r.drain(..r.len() - KEEP);
            }
        }
    }

    /// Forgets every reading (the panel's Clear).
    pub fn clear(&mut self) {
        self.records.clear();
    }

    /// The records as CSV, the layout's probes in order, over the times all of them have.
    pub fn csv(&self, layout: &doc::Layout) -> String {
        let names: Vec<String> = layout.probes.iter().map(|p| p.name.clone()).collect();
        let records: Vec<Vec<Reading>> = (layout.probes.iter())
            .map(|p| self.records.get(&p.id).cloned().unwrap_or_default())
            .collect();
        // Probes dropped later have fewer readings: the rows all of them have.
        let n = records.iter().map(Vec::len).min().unwrap_or(0);
        let tails: Vec<Vec<Reading>> = records.iter().map(|r| r[r.len() - n..].to_vec()).collect();
        probe::csv(&names, &tails)
    }
}

/// The colour of the `k`th probe's mark and lines.
pub fn colour(k: usize) -> Color32 {
    const C: [Color32; 6] = [
        Color32::from_rgb(255, 120, 200),
        Color32::from_rgb(120, 220, 255),
        Color32::from_rgb(255, 210, 90),
        Color32::from_rgb(150, 255, 140),
        Color32::from_rgb(200, 160, 255),
        Color32::from_rgb(255, 150, 100),
    ];
    C[k % C.len()]
}

impl EditorApp {
    /// Drops a probe at world point `at` as one edit, and selects it.
    pub fn add_probe(&mut self, ctx: &egui::Context, at: doc::Vec2) {
        let id = self.doc.next_id();
        let probe = doc::Probe {
            id,
            name: format!("Probe {}", self.doc.probes.len() + 1),
            pos: at,
        };
        if self.edit(
            ctx,
            Edit::AddProbe {
                index: usize::MAX,
                probe,
            },
        ) {
            self.selection = vec![Sel::Probe(id)];
        }
    }

    /// Writes the probes' records as CSV to `path`, atomically; says what it did.
    pub fn export_probes_csv(&mut self, ctx: &egui::Context, path: &std::path::Path) -> bool {
        let text = self.probe_log.csv(&self.doc);
        match crate::io::write_atomic(path, text.as_bytes()) {
            Ok(()) => {
                self.say(
                    ctx,
                    format!("Wrote the probes' readings to {}", path.display()),
                );
                true
            }
            Err(e) => {
                self.say(ctx, format!("cannot write {}: {e}", path.display()));
                false
            }
        }
    }
}

/// The probes' panel under the map: plots, statistics, Clear and Export.
pub fn panel(app: &mut EditorApp, ui: &mut egui::Ui) {
    if app.doc.probes.is_empty() {
        return;
    }
    let ctx = ui.ctx().clone();
    egui::Panel::bottom("probes")
        .resizable(false)
        .show(ui, |ui| {
            let open = app.settings.probes_open;
            ui.horizontal(|ui| {
                // Folded, the probes' readings now on one line; open, their plots.
                let size = egui::vec2(ui.spacing().icon_width, ui.spacing().interact_size.y);
                let (_, icon) = ui.allocate_exact_size(size, egui::Sense::click());
                let title = ui.add(
                    egui::Label::new(RichText::new("Probes").strong()).sense(egui::Sense::click()),
                );
                egui::collapsing_header::paint_default_icon(ui, if open { 1.0 } else { 0.0 }, &icon);
                let toggle = icon.union(title).on_hover_text(if open {
                    "Fold the probes away (their readings stay on this line)"
                } else {
                    "Show the probes' plots and statistics"
                });
                if toggle.clicked() {
                    app.settings.probes_open = !open;
                }
                if !open {
                    for (k, p) in app.doc.probes.iter().enumerate() {
                        let now = app.probe_log.records.get(&p.id).and_then(|r| r.last());
                        let text = match now {
                            Some(r) => format!(
                                "{} {:.1} m/s {:.0}°",
                                p.name,
                                r.speed(),
                                r.direction_deg()
                            ),
                            None => p.name.clone(),
                        };
                        ui.colored_label(colour(k), text);
                    }
                    return;
                }
                ui.weak("the live wind where each probe stands, since the last Reset");
                ui.with_layout(egui::Layout::right_to_left(egui::Align::Center), |ui| {
                    if ui
                        .button("Export CSV…")
                        .on_hover_text("Every reading: time, and each probe's speed, direction and components")
                        .clicked()
                    {
                        export(app, &ctx);
                    }
                    if ui.button("Clear").on_hover_text("Forget the readings so far").clicked() {
                        app.probe_log.clear();
                    }
                });
            });
            if !app.settings.probes_open {
                return;
            }
            let probes = app.doc.probes.clone();
            egui::Grid::new("probe stats").striped(true).show(ui, |ui| {
                for h in ["probe", "min", "mean", "max", "gust factor", "direction"] {
                    ui.strong(h);
                }
                ui.end_row();
                for (k, p) in probes.iter().enumerate() {
                    ui.colored_label(colour(k), p.name.as_str());
                    let rec = app.probe_log.records.get(&p.id).map_or(&[][..], |r| &r[..]);
                    match probe::stats(rec) {
                        Some(s) => {
                            ui.label(format!("{:.2} m/s", s.min));
                            ui.label(format!("{:.2} m/s", s.mean));
                            ui.label(format!("{:.2} m/s", s.max));
                            ui.label(if s.gust_factor.is_finite() {
                                format!("{:.2}", s.gust_factor)
                            } else {
                                "-".into()
                            })
                            .on_hover_text("The highest 3-second mean speed over the mean speed");
                            ui.label(format!("{:.0}°", s.mean_direction_deg))
                                .on_hover_text("The mean wind's direction: degrees from +x (east) toward +z (south)");
                        }
                        None => {
                            ui.weak("no readings yet: play the wind");
                        }
                    }
                    ui.end_row();
                }
            });
            let half = (ui.available_width() / 2.0 - 6.0).max(100.0);
            // A fixed height: a panel's room grows to what it holds.
            let height = PLOT_HEIGHT;
            ui.horizontal(|ui| {
                let series = |f: fn(&Reading) -> f32| -> Vec<(usize, String, Vec<[f64; 2]>)> {
                    (probes.iter().enumerate())
                        .map(|(k, p)| {
                            let r = app.probe_log.records.get(&p.id).map_or(&[][..], |r| &r[..]);
                            let pts = r.iter().map(|x| [x.time as f64, f(x) as f64]).collect();
                            (k, p.name.clone(), pts)
                        })
                        .collect()
                };
                let speed = series(Reading::speed);
                let direction = series(Reading::direction_deg);
                ui.vertical(|ui| {
                    ui.set_width(half);
                    ui.label(RichText::new("speed, m/s").small());
                    egui_plot::Plot::new("probe speed")
                        .height(height)
                        .width(half)
                        .include_y(0.0)
                        .legend(egui_plot::Legend::default())
                        .x_axis_label("s")
                        .show(ui, |plot| {
                            for (k, name, pts) in speed {
                                plot.line(egui_plot::Line::new(name, pts).color(colour(k)));
                            }
                        });
                });
                ui.vertical(|ui| {
                    ui.set_width(half);
                    ui.label(RichText::new("direction, degrees from east toward south").small());
                    egui_plot::Plot::new("probe direction")
                        .height(height)
                        .width(half)
                        .include_y(0.0)
                        .include_y(360.0)
                        .x_axis_label("s")
                        .show(ui, |plot| {
                            for (k, name, pts) in direction {
                                plot.points(
                                    egui_plot::Points::new(name, pts).color(colour(k)).radius(1.2),
                                );
                            }
                        });
                });
            });
        });
}

/// Export CSV…: the system's save dialog, or where it cannot open, a file beside the layout.
fn export(app: &mut EditorApp, ctx: &egui::Context) {
    let stem = app
        .doc
        .path()
        .and_then(|p| p.file_stem())
        .map_or("layout".to_string(), |s| s.to_string_lossy().into_owned());
    let name = format!("{stem}-probes.csv");
    let started = std::time::Instant::now();
    let picked = rfd::FileDialog::new()
        .set_file_name(&name)
        .add_filter("CSV", &["csv"])
        .save_file();
    match picked {
        Some(path) => {
            app.export_probes_csv(ctx, &path);
        }
        None if super::native_dialog_failed(started) => {
            let path = crate::io::layout_base(app.doc.path()).join(name);
            app.export_probes_csv(ctx, &path);
        }
        None => {}
    }
}
