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

/// A technique built on first use, with the passes that read its light.
struct Built<T> {
    technique: T,
    shading: Shading,
}

impl<T: ShadowTechnique> Built<T> {
    /// `technique` leaving out `excluded`, and its shading.
    fn new(ctx: &GpuContext, mut technique: T, layouts: &Layouts, excluded: &[u32]) -> Self {
        technique.exclude(excluded);
        let shading = Shading::new(
            ctx,
            &technique,
            [&layouts.frame, &layouts.measure],
            layouts.early_depth_test,
        );
        Self { technique, shading }
    }
}

/// What a technique and its shading are built against.
struct Layouts {
    frame: wgpu::BindGroupLayout,
    pass_view: wgpu::BindGroupLayout,
    measure: wgpu::BindGroupLayout,
    early_depth_test: bool,
}

/// Every technique and its shading; one is active. The shadow maps are built at once (every
/// frame before the first asks for them, and the window opens on them); the others when a
/// frame first asks for them, so that a frame of one technique pays for no other's pipelines
/// (shadow volumes' compute passes alone take seconds to compile on a software adapter).
pub(super) struct Techniques {
    pub maps: MapTechnique,
    map_shading: Shading,
    volumes: Option<Built<VolumeTechnique>>,
    layered: Option<Built<LayeredTechnique>>,
    virtual_maps: Option<Built<VirtualTechnique>>,
    layouts: Layouts,
    active: Family,
    /// The instances every technique leaves out, also those built later.
    excluded: Vec<u32>,
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
        Self {
            map_shading: Shading::new(ctx, &maps, [frame, measure], early_depth_test),
            maps,
            volumes: None,
            layered: None,
            virtual_maps: None,
            layouts: Layouts {
                frame: frame.clone(),
                pass_view: pass_view.clone(),
                measure: measure.clone(),
                early_depth_test,
            },
            active: Family::Maps,
            excluded: Vec::new(),
            layout_key: None,
            refusals: crate::gpu::LogOnce::default(),
        }
    }

    /// Makes `family` the active technique, building it and its shading on its first use.
    pub fn activate(&mut self, ctx: &GpuContext, family: Family) {
        let (layouts, excluded) = (&self.layouts, self.excluded.as_slice());
        match family {
            Family::Maps => {}
            Family::Volumes => {
                self.volumes.get_or_insert_with(|| {
                    let volumes = VolumeTechnique::new(ctx, &layouts.frame);
                    Built::new(ctx, volumes, layouts, excluded)
                });
            }
            Family::Lights => {
                self.layered.get_or_insert_with(|| {
                    let layered = LayeredTechnique::new(ctx, [&layouts.frame, &layouts.pass_view]);
                    Built::new(ctx, layered, layouts, excluded)
                });
            }
            Family::Virtual => {
                self.virtual_maps.get_or_insert_with(|| {
                    let virtual_maps = VirtualTechnique::new(ctx, &layouts.frame);
                    Built::new(ctx, virtual_maps, layouts, excluded)
                });
            }
        }
        self.active = family;
    }

    /// Drops the active technique after an allocation of its failed (what it holds is
    /// invalid); it is built again, with the exclusions, when a frame next asks for it.
    pub fn discard_active(&mut self, ctx: &GpuContext) {
        match self.active {
            Family::Maps => {
                let layouts = &self.layouts;
                let mut maps = MapTechnique::new(ctx, &layouts.frame, &layouts.pass_view);
                maps.exclude(&self.excluded);
                self.map_shading = Shading::new(
                    ctx,
                    &maps,
                    [&layouts.frame, &layouts.measure],
                    layouts.early_depth_test,
                );
                self.maps = maps;
                self.layout_key = None;
            }
            Family::Volumes => self.volumes = None,
            Family::Lights => self.layered = None,
            Family::Virtual => self.virtual_maps = None,
        }
    }

    pub fn active_family(&self) -> Family {
        self.active
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
        if let Some(built) = &mut self.layered {
            built.technique.set_sun(sun);
        }
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

    /// The shadow volumes, once a frame has used them.
    pub fn volumes(&self) -> Option<&VolumeTechnique> {
        self.volumes.as_ref().map(|b| &b.technique)
    }

    /// The many lights' maps, once a frame has used them.
    pub fn layered(&self) -> Option<&LayeredTechnique> {
        self.layered.as_ref().map(|b| &b.technique)
    }

    /// The virtual maps, once a frame has used them.
    pub fn virtual_maps(&self) -> Option<&VirtualTechnique> {
        self.virtual_maps.as_ref().map(|b| &b.technique)
    }

    /// The active technique and its shading.
    fn active_built(&self) -> (&dyn ShadowTechnique, &Shading) {
        fn pair<T: ShadowTechnique>(built: Option<&Built<T>>) -> (&dyn ShadowTechnique, &Shading) {
            let built = built.expect("a technique is built when it is activated");
            (&built.technique, &built.shading)
        }
        match self.active {
            Family::Maps => (&self.maps, &self.map_shading),
            Family::Volumes => pair(self.volumes.as_ref()),
            Family::Lights => pair(self.layered.as_ref()),
            Family::Virtual => pair(self.virtual_maps.as_ref()),
        }
    }

    pub fn active(&self) -> &dyn ShadowTechnique {
        self.active_built().0
    }

    pub fn active_mut(&mut self) -> &mut dyn ShadowTechnique {
        fn technique<T: ShadowTechnique>(built: Option<&mut Built<T>>) -> &mut dyn ShadowTechnique {
            &mut built
                .expect("a technique is built when it is activated")
                .technique
        }
        match self.active {
            Family::Maps => &mut self.maps,
            Family::Volumes => technique(self.volumes.as_mut()),
            Family::Lights => technique(self.layered.as_mut()),
            Family::Virtual => technique(self.virtual_maps.as_mut()),
        }
    }

    /// The active technique's shading.
    pub fn shading(&self) -> &Shading {
        self.active_built().1
    }

    /// Every technique leaves these instances out, also those built later.
    pub fn exclude(&mut self, instances: &[u32]) {
        self.excluded = instances.to_vec();
        self.maps.exclude(instances);
        let built: [Option<&mut dyn ShadowTechnique>; 3] = [
            self.volumes.as_mut().map(|b| &mut b.technique as _),
            self.layered.as_mut().map(|b| &mut b.technique as _),
            self.virtual_maps.as_mut().map(|b| &mut b.technique as _),
        ];
        for technique in built.into_iter().flatten() {
            technique.exclude(instances);
        }
    }
}
