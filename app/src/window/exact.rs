//! The exact shadow in the window. While measuring, once the view has been still for a frame,
//! a worker thread casts its rays (`render_core::truth`) with its own copy of the scene; when
//! they come back for the view still on screen, the last frame's light is read at their
//! points on the GPU (once per view and setting, read back a frame or more later) and the
//! Counts tab shows the error. The loop waits neither for the rays nor for the GPU.

use std::sync::mpsc;

use render_core::frame::FrameSettings;
use render_core::geom::Camera;
use render_core::gpu::GpuError;
use render_core::metrics::ShadowError;
use render_core::scene::{Instance, Scene, ShadowLight};
use render_core::truth::{ExactShadow, PendingLight, SceneRays, ViewKey};

/// What a view's truth depends on that the window changes.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct ViewOf {
    pub camera: Camera,
    pub size: (u32, u32),
    pub light: ShadowLight,
}

impl ViewOf {
    fn of(key: &ViewKey) -> Self {
        Self {
            camera: key.camera,
            size: (key.width, key.height),
            light: key.light,
        }
    }
}

enum Request {
    /// The scene the following views are of.
    Scene(Box<Scene>),
    /// A view, with the instances as posed now.
    View(ViewOf, Vec<Instance>),
}

/// The worker, and what came back.
pub(super) struct ExactInWindow {
    requests: mpsc::Sender<Request>,
    results: mpsc::Receiver<ExactShadow>,
    scene_sent: bool,
    requested: Option<ViewOf>,
    last_view: Option<ViewOf>,
    /// The newest truth that came back.
    exact: Option<ExactShadow>,
    /// Its comparison with the frame under these settings.
    compared: Option<(FrameSettings, ShadowError)>,
    /// The light at its points under these settings, on its way back from the GPU.
    comparing: Option<(FrameSettings, PendingLight)>,
}

impl ExactInWindow {
    /// A worker for one scene (a new scene gets a new one).
    pub fn new() -> Self {
        let (requests, inbox) = mpsc::channel::<Request>();
        let (outbox, results) = mpsc::channel();
        std::thread::Builder::new()
            .name("exact shadow".into())
            .spawn(move || work(&inbox, &outbox))
            .expect("the exact shadow's thread starts");
        Self {
            requests,
            results,
            scene_sent: false,
            requested: None,
            last_view: None,
            exact: None,
            compared: None,
            comparing: None,
        }
    }

    /// After a frame of `view`: asks for its truth once it has been still for a frame, and
    /// takes what came back. Returns a truth to compare with the frame when one is due.
    pub fn after_frame(
        &mut self,
        scene: &Scene,
        view: ViewOf,
        settings: &FrameSettings,
    ) -> Option<&ExactShadow> {
        let wanted = settings.measure && !settings.animate && settings.observer.is_none();
        if wanted && self.last_view == Some(view) && self.requested != Some(view) {
            if !self.scene_sent {
                self.scene_sent = self
                    .requests
                    .send(Request::Scene(Box::new(scene.clone())))
                    .is_ok();
            }
            if self
                .requests
                .send(Request::View(view, scene.instances.clone()))
                .is_ok()
            {
                self.requested = Some(view);
            }
        }
        self.last_view = Some(view);
        while let Ok(exact) = self.results.try_recv() {
            self.exact = Some(exact);
            self.compared = None;
            self.comparing = None;
        }
        let exact = self.exact.as_ref()?;
        let due = wanted
            && self.comparing.is_none()
            && ViewOf::of(&exact.key) == view
            && self.compared.as_ref().is_none_or(|(s, _)| s != settings);
        due.then_some(exact)
    }

    /// The light of the frame under `settings` at the truth's points, on its way.
    pub fn comparing(&mut self, settings: &FrameSettings, light: PendingLight) {
        self.comparing = Some((*settings, light));
    }

    /// Takes the light that came back (after a device poll) and compares it with the truth.
    pub fn poll(&mut self) -> Result<(), GpuError> {
        let Some(light) = self.comparing.as_ref().and_then(|(_, l)| l.try_take()) else {
            return Ok(());
        };
        let (settings, _) = self.comparing.take().expect("checked above");
        if let Some(exact) = &self.exact {
            self.compared = Some((settings, exact.error_of(&light?)));
        }
        Ok(())
    }

    /// The error of `view` under `settings`, if it was compared.
    pub fn error_of(&self, view: ViewOf, settings: &FrameSettings) -> Option<ShadowError> {
        let exact = self.exact.as_ref()?;
        let (s, error) = self.compared.as_ref()?;
        (ViewOf::of(&exact.key) == view && s == settings && settings.measure).then_some(*error)
    }
}

/// Casts the newest view asked for; older requests still waiting are skipped.
fn work(inbox: &mpsc::Receiver<Request>, outbox: &mpsc::Sender<ExactShadow>) {
    let mut scene: Option<Box<Scene>> = None;
    let mut rays: Option<SceneRays> = None;
    while let Ok(first) = inbox.recv() {
        let mut view = None;
        for request in std::iter::once(first).chain(inbox.try_iter()) {
            match request {
                Request::Scene(s) => {
                    scene = Some(s);
                    rays = None;
                }
                Request::View(v, instances) => view = Some((v, instances)),
            }
        }
        let (Some((view, instances)), Some(scene)) = (view, scene.as_deref()) else {
            continue;
        };
        let rays = rays.get_or_insert_with(|| SceneRays::new(scene));
        rays.sync(&instances);
        let key = ViewKey {
            camera: view.camera,
            width: view.size.0,
            height: view.size.1,
            light: view.light,
            poses: rays.version,
        };
        if outbox.send(ExactShadow::cast(rays, key)).is_err() {
            return;
        }
    }
}
