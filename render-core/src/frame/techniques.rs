//! The frame's shadow techniques, each with the passes composed with its light term: the
//! camera's shading and the light at the truth's points. The setup chooses which one a frame
//! runs ([`Family::of`]); the frame talks to it only through [`ShadowTechnique`].

use super::camera::CameraPasses;
use super::{FrameSettings, LispsmSettings, ShadowSetup};
use crate::cascades::{CascadeSettings, Cascades};
use crate::gpu::GpuContext;
use crate::layered::LayeredTechnique;
use crate::shadow_map::{GivenViews, MapTechnique, SunView, ViewLayout, WarpedSunView};
use crate::shadow_view::ShadowView;
use crate::technique::ShadowTechnique;
use crate::truth::LightAtPoints;
use crate::virtual_maps::VirtualTechnique;
use crate::volumes::VolumeTechnique;

/// What the single map renders: its view fitted to the camera, `copies` times (more than one
/// only in tests of the per-view path), or views a test chose (a virtual level's texel grid).
#[derive(Clone, Debug, PartialEq)]
pub(super) enum SingleViews {
    Fitted { copies: u32 },
    Given(Vec<ShadowView>),
}

/// Which technique a setup belongs to.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub(super) enum Family {
    /// Shadow maps: a single map, LiSPSM or cascades (`shadow_map/`).
    #[default]
    Maps,
    /// Stencil shadow volumes (`volumes/`).
    Volumes,
    /// Many lights, a map each (`layered/`).
    Lights,
    /// Virtual shadow maps (`virtual_maps/`).
    Virtual,
}

impl Family {
    pub fn of(setup: ShadowSetup) -> Self {
        match setup {
            ShadowSetup::Single | ShadowSetup::Lispsm | ShadowSetup::Cascades => Self::Maps,
            ShadowSetup::Volumes => Self::Volumes,
            ShadowSetup::Lights => Self::Lights,
            ShadowSetup::Virtual => Self::Virtual,
        }
    }

    /// Why this family cannot cast a point light's shadows (`None`: it can). The frame then
    /// draws the point light's light without shadows and reports this.
    pub fn point_light_refusal(self) -> Option<&'static str> {
        match self {
            Self::Maps => Some(
                "shadow maps cast the sun's shadows only: a point or spot light's need \
                 `--shadow volumes` or `--shadow virtual` (cube maps come with many lights, \
                 issue 14); drawn without shadows",
            ),
            Self::Volumes | Self::Virtual => None,
            Self::Lights => Some(
                "`--light point` is for shadow volumes and virtual maps: the many-lights \
                 technique shadows every light of the scene, and drops the one light in place of \
                 the sun",
            ),
        }
    }
}

/// The passes that read a technique's light term.
pub(super) struct Shading {
    pub camera: CameraPasses,
    pub at_points: LightAtPoints,
}

impl Shading {
    fn new(
        ctx: &GpuContext,
        technique: &dyn ShadowTechnique,
        [frame, measure]: [&wgpu::BindGroupLayout; 2],
        early_depth_test: bool,
    ) -> Self {
        let (light_wgsl, light_layout) = technique.light_term();
        let layouts = [frame, light_layout, measure];
        Self {
            camera: CameraPasses::new(&ctx.device, light_wgsl, layouts, early_depth_test),
            at_points: LightAtPoints::new(&ctx.device, light_wgsl, layouts),
        }
    }
}

/// Every technique and its shading; one is active.
pub(super) struct Techniques {
    pub maps: MapTechnique,
    volumes: VolumeTechnique,
    layered: LayeredTechnique,
    map_shading: Shading,
    volume_shading: Shading,
    layered_shading: Shading,
    virtual_maps: VirtualTechnique,
    virtual_shading: Shading,
    pub active: Family,
    /// What the map technique's layout was made for (setup, cascades, LiSPSM, single views).
    layout_key: Option<(ShadowSetup, CascadeSettings, LispsmSettings, SingleViews)>,
    /// The active one cannot cast the frame's point light's shadows: logged once.
    refusals: crate::gpu::LogOnce,
}

impl Techniques {
    /// `layouts`: group 0 of scene passes, one view's uniform slice, the measure group.
    pub fn new(
        ctx: &GpuContext,
        [frame, pass_view, measure]: [&wgpu::BindGroupLayout; 3],
        early_depth_test: bool,
    ) -> Self {
        let maps = MapTechnique::new(ctx, frame, pass_view);
        let volumes = VolumeTechnique::new(ctx, frame);
        let layered = LayeredTechnique::new(ctx, [frame, pass_view]);
        let virtual_maps = VirtualTechnique::new(ctx, frame);
        Self {
            virtual_shading: Shading::new(ctx, &virtual_maps, [frame, measure], early_depth_test),
            virtual_maps,
            map_shading: Shading::new(ctx, &maps, [frame, measure], early_depth_test),
            volume_shading: Shading::new(ctx, &volumes, [frame, measure], early_depth_test),
            layered_shading: Shading::new(ctx, &layered, [frame, measure], early_depth_test),
            maps,
            volumes,
            layered,
            active: Family::Maps,
            layout_key: None,
            refusals: crate::gpu::LogOnce::default(),
        }
    }

    /// The views `settings` ask of the techniques: the map technique's layout (the single
    /// map as `single` says, LiSPSM, cascades), remade when they change; many lights'
    /// cascades of the sun, where it shines with them.
    pub fn arrange(&mut self, settings: &FrameSettings, single: &SingleViews) {
        let same = self.layout_key.as_ref().is_some_and(|k| {
            (k.0, k.1, k.2) == (settings.setup, settings.cascades, settings.lispsm)
                && k.3 == *single
        });
        if !same {
            let layout: Box<dyn ViewLayout> = match (settings.setup, single) {
                (ShadowSetup::Lispsm, _) => Box::new(WarpedSunView {
                    n_scale: settings.lispsm.n_scale,
                }),
                (ShadowSetup::Cascades, _) => Box::new(Cascades::new(settings.cascades)),
                (_, SingleViews::Fitted { copies }) => Box::new(SunView { copies: *copies }),
                (_, SingleViews::Given(views)) => Box::new(GivenViews(views.clone())),
            };
            self.maps.set_layout(layout);
            self.layout_key = Some((
                settings.setup,
                settings.cascades,
                settings.lispsm,
                single.clone(),
            ));
        }
        let sun = settings
            .layered
            .sun
            .then(|| Cascades::new(settings.cascades));
        self.layered.set_sun(sun);
    }

    /// Where the active technique cannot cast `settings`' point light's shadows, turns
    /// shadows off and says why (logged once).
    pub fn refuse_point_light(
        &mut self,
        settings: &mut super::FrameSettings,
    ) -> Option<&'static str> {
        let refusal = settings.point_light.and(self.active.point_light_refusal());
        match refusal {
            Some(refusal) if self.active == Family::Lights => {
                settings.point_light = None;
                self.refusals.warn(refusal);
            }
            Some(refusal) => {
                settings.shadow.shadows_enabled = false;
                self.refusals.warn(refusal);
            }
            None => self.refusals.clear(),
        }
        refusal
    }

    pub fn volumes(&self) -> &VolumeTechnique {
        &self.volumes
    }

    pub fn layered(&self) -> &LayeredTechnique {
        &self.layered
    }

    pub fn virtual_maps(&self) -> &VirtualTechnique {
        &self.virtual_maps
    }

    pub fn active(&self) -> &dyn ShadowTechnique {
        match self.active {
            Family::Maps => &self.maps,
            Family::Volumes => &self.volumes,
            Family::Lights => &self.layered,
            Family::Virtual => &self.virtual_maps,
        }
    }

    pub fn active_mut(&mut self) -> &mut dyn ShadowTechnique {
        match self.active {
            Family::Maps => &mut self.maps,
            Family::Volumes => &mut self.volumes,
            Family::Lights => &mut self.layered,
            Family::Virtual => &mut self.virtual_maps,
        }
    }

    /// The active technique's shading.
    pub fn shading(&self) -> &Shading {
        match self.active {
            Family::Maps => &self.map_shading,
            Family::Volumes => &self.volume_shading,
            Family::Lights => &self.layered_shading,
            Family::Virtual => &self.virtual_shading,
        }
    }

    /// Every technique leaves these instances out.
    pub fn exclude(&mut self, instances: &[u32]) {
        self.maps.exclude(instances);
        self.volumes.exclude(instances);
        self.layered.exclude(instances);
        self.virtual_maps.exclude(instances);
    }
}
