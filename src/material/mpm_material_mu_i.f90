!> The mu(I) rheology of dense granular flow (Jop, Forterre and Pouliquen 2006, Nature 441:727)
!> as an elasto-plastic law with the return of Dunatunga and Kamrin (2015, J. Fluid Mech.
!> 779:483).
!>
!> Stress is tension positive (`mpm_stress`). With the pressure p = -tr(sigma)/3 (compression
!> positive), the deviator s and the equivalent shear stress tau = sqrt(s:s/2) = sqrt(J2), the
!> material flows when tau exceeds mu(I) p, with the friction coefficient
!>
!>     mu(I) = mu_s + (mu_2 - mu_s) / (I_0 / I + 1),   I = gamma_dot_p d / sqrt(p / rho_s),
!>
!> gamma_dot_p = sqrt(2) |D_p| the equivalent plastic shear rate (the shear rate in simple
!> shear), d the grain diameter and rho_s the grain density. The plastic flow is deviatoric
!> (no dilatancy) and along the deviator, D_p = gamma_dot_p s / (2 tau).
!>
!> Return (Dunatunga and Kamrin 2015, section 3): an objective elastic trial stress (p_tr,
!> tau_tr); p_tr <= 0: no contact, the stress is zero; tau_tr <= mu_s p_tr: elastic;
!> otherwise the deviator shrinks radially at p = p_tr to tau = tau_tr - G dt gamma_dot_p with
!> tau = mu(I(gamma_dot_p)) p, one equation in gamma_dot_p whose root is the positive root of
!> a quadratic (see `flow_return`). The rate in I is thus the plastic part of the particle's
!> deviatoric strain rate over the step (in steady flow all of it), not its total rate: during
!> elastic loading that total rate would raise mu before anything flows.
!>
!> In plane strain at zero rate this is the Drucker-Prager cone of the plane-strain match with
!> psi = 0, alpha = sin(phi), k = 0 (`mpm_material_drucker_prager`): mu_s = sin(phi) of the
!> Mohr-Coulomb friction angle phi that gives the same strength in plane strain.
!>
!> State of a particle: state(1) = accumulated equivalent plastic shear strain eps_q [-]; with
!> `separation` (`mpm_separation`), state(2) = opening strain [-]: the volumetric strain the
!> material took beyond zero pressure, which compression closes before any stress builds.
!>
!> `materials[i].type = "mu_i"`: keys `E` and `nu` or `K` and `G`, `rho`, `mu_s`, `mu_2`, `I_0`,
!> `grain_diameter`, `grain_density`, `separation`.
module mpm_material_mu_i
    use mpm_kinds, only: wp
    use mpm_error, only: error_type
    use mpm_strings, only: fmt_real
    use mpm_case_cursor, only: cursor_type
    use mpm_separation, only: close_opening
    use mpm_material, only: material_key_width, work_plastic
    use mpm_elastic_solid, only: elastic_solid_type, add_elastic_trial
    use mpm_stress, only: mean_and_deviator
    implicit none
    private
    public :: mu_i_material_type, new_mu_i_material, mu_i_friction, mu_i_inertial_number

    real(wp), parameter :: sqrt3 = sqrt(3.0_wp)

    !> A granular material of the mu(I) rheology; E, nu, rho, G and lambda come from
    !> `elastic_solid_type`.
    type, extends(elastic_solid_type) :: mu_i_material_type
        real(wp) :: bulk = 0.0_wp
            !! bulk modulus K [Pa]
        real(wp) :: mu_s = 0.0_wp
            !! friction coefficient at zero inertial number, tau / p [-]
        real(wp) :: mu_2 = 0.0_wp
            !! friction coefficient as I goes to infinity, >= mu_s [-]
        real(wp) :: i_0 = 0.0_wp
            !! inertial number at which mu is halfway between mu_s and mu_2 [-]
        real(wp) :: grain_diameter = 0.0_wp
            !! grain diameter d [m]
        real(wp) :: grain_density = 0.0_wp
            !! density of the grains' solid rho_s [kg/m3]
        logical :: separation = .true.
            !! keep the opening of a material pulled apart (state(2), `mpm_separation`)
    contains
        procedure, nopass :: names => mu_i_names
        procedure, nopass :: keys => mu_i_keys
        procedure :: read => mu_i_read
        procedure :: writes_plastic_strain => mu_i_writes_plastic_strain
        procedure :: summary => mu_i_summary
        procedure :: update_stress => mu_i_update_stress
            !! elastic predictor and the mu(I) return of one particle over one step
        procedure :: nstate => mu_i_nstate
            !! eps_q, and the opening strain with separation
        procedure :: work_kind => mu_i_work_kind
            !! the work beyond the stored elastic energy is dissipated (plastic)
    end type mu_i_material_type

contains

    !> Names accepted for `type`.
    pure subroutine mu_i_names(list)
        character(len=material_key_width), allocatable, intent(out) :: list(:)
            !! the names

        list = [character(len=material_key_width) :: "mu_i"]
    end subroutine mu_i_names

    !> Keys of a mu(I) material.
    pure subroutine mu_i_keys(list)
        character(len=material_key_width), allocatable, intent(out) :: list(:)
            !! the keys

        list = [character(len=material_key_width) :: "name", "type", "E", "nu", "K", "G", &
            "rho", "mu_s", "mu_2", "I_0", "grain_diameter", "grain_density", "separation"]
    end subroutine mu_i_keys

    !> Elasticity (`E` and `nu`, or `K` and `G`), `rho`, the rheology and `separation`.
    subroutine mu_i_read(self, item, error)
        class(mu_i_material_type), intent(inout) :: self
            !! the material
        type(cursor_type), intent(in) :: item
            !! the material object ("materials[i]")
        type(error_type), allocatable, intent(out) :: error
            !! first error found

        real(wp) :: young, poisson, bulk, shear, density, mu_s, mu_2, i_0, diameter, solid
        logical :: separation

        call read_elastic_pair(item, young, poisson, error)
        if (allocated(error)) return
        density = 0.0_wp
        call item%get_real("rho", density, error, required=.true., above=0.0_wp, unit="kg/m3")
        if (allocated(error)) return
        mu_s = 0.0_wp
        call item%get_real("mu_s", mu_s, error, required=.true., above=0.0_wp)
        if (allocated(error)) return
        mu_2 = 0.0_wp
        call item%get_real("mu_2", mu_2, error, required=.true., above=0.0_wp)
        if (allocated(error)) return
        if (mu_2 < mu_s) then
            call item%fail(error, item%key_path("mu_2")//" = "//fmt_real(mu_2) &
                //" is below mu_s = "//fmt_real(mu_s)//": the friction cannot fall with the " &
                //"inertial number; give mu_2 >= mu_s (mu_2 = mu_s: a rate-independent friction)")
            return
        end if
        i_0 = 0.0_wp
        call item%get_real("I_0", i_0, error, required=.true., above=0.0_wp)
        if (allocated(error)) return
        diameter = 0.0_wp
        call item%get_real("grain_diameter", diameter, error, required=.true., above=0.0_wp, &
            unit="m")
        if (allocated(error)) return
        solid = 0.0_wp
        call item%get_real("grain_density", solid, error, required=.true., above=0.0_wp, &
            unit="kg/m3")
        if (allocated(error)) return
        separation = .true.
        call item%get_bool("separation", separation, error)
        if (allocated(error)) return
        bulk = young/(3.0_wp*(1.0_wp - 2.0_wp*poisson))
        shear = young/(2.0_wp*(1.0_wp + poisson))
        call new_mu_i_material(self, bulk, shear, density, mu_s, mu_2, i_0, diameter, solid, &
            separation)
    end subroutine mu_i_read

    !> `E` and `nu`, or `K` and `G` (one pair, whole), as E and nu.
    subroutine read_elastic_pair(item, young, poisson, error)
        type(cursor_type), intent(in) :: item
            !! the material object
        real(wp), intent(out) :: young
            !! Young's modulus [Pa]
        real(wp), intent(out) :: poisson
            !! Poisson's ratio [-]
        type(error_type), allocatable, intent(out) :: error
            !! first error found

        real(wp) :: bulk, shear
        logical :: by_moduli

        young = 0.0_wp
        poisson = 0.0_wp
        by_moduli = item%has("K") .or. item%has("G")
        if (by_moduli .and. (item%has("E") .or. item%has("nu"))) then
            call item%fail(error, item%path//" gives both E/nu and K/G: the elasticity of a " &
                //"mu_i material is one pair, either E and nu or K and G")
            return
        end if
        if (.not. by_moduli) then
            call item%get_real("E", young, error, required=.true., above=0.0_wp, unit="Pa")
            if (allocated(error)) return
            call item%get_real("nu", poisson, error, required=.true., at_least=0.0_wp, &
                below=0.5_wp)
            return
        end if
        bulk = 0.0_wp
        shear = 0.0_wp
        call item%get_real("K", bulk, error, required=.true., above=0.0_wp, unit="Pa")
        if (allocated(error)) return
        call item%get_real("G", shear, error, required=.true., above=0.0_wp, unit="Pa")
        if (allocated(error)) return
        poisson = (3.0_wp*bulk - 2.0_wp*shear)/(2.0_wp*(3.0_wp*bulk + shear))
        if (poisson < 0.0_wp) then
            call item%fail(error, item%path//": K = "//fmt_real(bulk)//" Pa and G = " &
                //fmt_real(shear)//" Pa give nu = "//fmt_real(poisson) &
                //" < 0; allowed: G <= 1.5 K (nu >= 0 and < 0.5)")
            return
        end if
        young = 9.0_wp*bulk*shear/(3.0_wp*bulk + shear)
    end subroutine read_elastic_pair

    !> Construct a mu(I) material from its moduli, density and rheology.
    pure subroutine new_mu_i_material(mat, bulk, shear, density, mu_s, mu_2, i_0, diameter, &
            solid, separation)
        class(mu_i_material_type), intent(inout) :: mat
            !! the material
        real(wp), intent(in) :: bulk
            !! bulk modulus K [Pa]
        real(wp), intent(in) :: shear
            !! shear modulus G [Pa]
        real(wp), intent(in) :: density
            !! mass density of the material [kg/m3]
        real(wp), intent(in) :: mu_s
            !! friction at zero inertial number [-]
        real(wp), intent(in) :: mu_2
            !! friction as I goes to infinity [-]
        real(wp), intent(in) :: i_0
            !! inertial number scale I_0 [-]
        real(wp), intent(in) :: diameter
            !! grain diameter [m]
        real(wp), intent(in) :: solid
            !! grain density [kg/m3]
        logical, intent(in) :: separation
            !! keep the opening of a material pulled apart

        call mat%set_elasticity(9.0_wp*bulk*shear/(3.0_wp*bulk + shear), &
            (3.0_wp*bulk - 2.0_wp*shear)/(2.0_wp*(3.0_wp*bulk + shear)), density)
        mat%bulk = bulk
        mat%shear = shear
        mat%lame = bulk - 2.0_wp*shear/3.0_wp
        mat%mu_s = mu_s
        mat%mu_2 = mu_2
        mat%i_0 = i_0
        mat%grain_diameter = diameter
        mat%grain_density = solid
        mat%separation = separation
    end subroutine new_mu_i_material

    !> The plastic shear strain is the state this material writes.
    pure logical function mu_i_writes_plastic_strain(self)
        class(mu_i_material_type), intent(in) :: self
            !! the material

        mu_i_writes_plastic_strain = .true.
    end function mu_i_writes_plastic_strain

    !> The elastic line, then the rheology.
    pure subroutine mu_i_summary(self, text)
        class(mu_i_material_type), intent(in) :: self
            !! the material
        character(len=:), allocatable, intent(out) :: text
            !! the lines

        call self%elasticity_summary(text)
        text = text//"    mu(I): mu_s = "//fmt_real(self%mu_s)//", mu_2 = "//fmt_real(self%mu_2) &
            //", I_0 = "//fmt_real(self%i_0)//", grain diameter "//fmt_real(self%grain_diameter) &
            //" m, grain density "//fmt_real(self%grain_density)//" kg/m3" &
            //merge(", separation", "            ", self%separation)
        text = trim(text)//new_line("a")
    end subroutine mu_i_summary

    !> One state value, eps_q, and with separation the opening strain.
    pure integer function mu_i_nstate(self)
        class(mu_i_material_type), intent(in) :: self
            !! the material

        mu_i_nstate = merge(2, 1, self%separation)
    end function mu_i_nstate

    !> Where the work of the stresses goes: plastic dissipation beyond the stored part.
    pure integer function mu_i_work_kind(self)
        class(mu_i_material_type), intent(in) :: self
            !! the material

        mu_i_work_kind = work_plastic
    end function mu_i_work_kind

    !> Inertial number I = gamma_dot d / sqrt(p / rho_s) of a shear rate at a pressure.
    pure real(wp) function mu_i_inertial_number(mat, rate, pressure)
        type(mu_i_material_type), intent(in) :: mat
            !! the material
        real(wp), intent(in) :: rate
            !! equivalent shear rate gamma_dot >= 0 [1/s]
        real(wp), intent(in) :: pressure
            !! pressure p > 0, compression positive [Pa]

        mu_i_inertial_number = rate*mat%grain_diameter*sqrt(mat%grain_density/pressure)
    end function mu_i_inertial_number

    !> Friction coefficient mu(I) = mu_s + (mu_2 - mu_s) I / (I_0 + I), the form of
    !> (mu_2 - mu_s) / (I_0 / I + 1) that holds at I = 0.
    pure real(wp) function mu_i_friction(mat, inertial)
        type(mu_i_material_type), intent(in) :: mat
            !! the material
        real(wp), intent(in) :: inertial
            !! inertial number I >= 0 [-]

        mu_i_friction = mat%mu_s + (mat%mu_2 - mat%mu_s)*inertial/(mat%i_0 + inertial)
    end function mu_i_friction

    !> The return's shear stress tau = mu(I) p and its drop xi = tau_tr - tau = G dt
    !> gamma_dot_p, from tau_tr - xi = p mu(I), I = I_0 xi / c.
    !>
    !> With S = tau_tr - mu_s p > 0, dmu = mu_2 - mu_s and c = I_0 G dt sqrt(p / rho_s) / d
    !> (the stress drop at which I = I_0), mu(I) = mu_s + dmu xi / (c + xi), so
    !> (S - xi)(c + xi) = p dmu xi: the quadratic xi^2 + B xi - S c = 0, B = c + p dmu - S.
    !> Its left side is -S c < 0 at xi = 0 and p dmu S >= 0 at xi = S, so its positive root
    !> lies in (0, S]: the returned tau lies between mu_s p and tau_tr. Each branch of the root
    !> formula is the one without cancellation, and c goes to 0 as p goes to 0 (I_0 / c, the
    !> factor of I, would overflow). tau is then p mu(I) of that root, not tau_tr - xi, which
    !> would cancel when p mu is far below tau_tr (a fast step at a tiny pressure). When S c
    !> underflows to zero, I is infinite for any flow: tau = min(tau_tr, mu_2 p). dt <= 0
    !> (never passed by the solver): the rate-free return tau = mu_s p.
    pure subroutine flow_return(mat, tau_tr, p, dt, tau, xi)
        type(mu_i_material_type), intent(in) :: mat
            !! the material
        real(wp), intent(in) :: tau_tr
            !! trial equivalent shear stress, above mu_s p [Pa]
        real(wp), intent(in) :: p
            !! pressure, > 0 [Pa]
        real(wp), intent(in) :: dt
            !! time step [s]
        real(wp), intent(out) :: tau
            !! returned equivalent shear stress [Pa]
        real(wp), intent(out) :: xi
            !! its drop, tau_tr - tau [Pa]

        real(wp) :: s, c, bq, root, dmu

        s = tau_tr - mat%mu_s*p
        dmu = mat%mu_2 - mat%mu_s
        c = 0.0_wp
        if (dt > 0.0_wp) c = mat%i_0*mat%shear*dt*sqrt(p/mat%grain_density)/mat%grain_diameter
        bq = c + p*dmu - s
        root = sqrt(bq*bq + 4.0_wp*s*c)
        if (dt <= 0.0_wp) then
            tau = mat%mu_s*p
        else if (bq >= 0.0_wp) then
            xi = 2.0_wp*s*c/(bq + root)
            if (xi > 0.0_wp) then
                tau = p*(mat%mu_s + dmu*xi/(c + xi))
            else
                tau = min(tau_tr, mat%mu_2*p)
            end if
        else
            xi = 0.5_wp*(root - bq)
            tau = p*(mat%mu_s + dmu*xi/(c + xi))
        end if
        tau = min(max(tau, mat%mu_s*p), tau_tr)
        xi = tau_tr - tau
    end subroutine flow_return

    !> Objective elastic trial stress, then the return of Dunatunga and Kamrin (2015): zero
    !> stress without pressure, elastic below mu_s p, else the radial return at constant
    !> pressure to tau = mu(I) p with I from the plastic shear rate of the step.
    pure subroutine mu_i_update_stress(self, stress, dstrain, omega, dt, state)
        class(mu_i_material_type), intent(in) :: self
            !! the material
        real(wp), intent(inout) :: stress(:)
            !! Cauchy stress, 4 (2D) or 6 (3D) components, tension positive [Pa]
        real(wp), intent(in) :: dstrain(:)
            !! strain increment, tensor components [-]
        real(wp), intent(in) :: omega(3)
            !! spin increment W dt (xy, yz, zx) [-]
        real(wp), intent(in) :: dt
            !! time step [s]
        real(wp), intent(inout) :: state(:)
            !! state(1) eps_q [-], with separation state(2) opening strain [-]

        real(wp) :: m_tr, p, tau_tr, tau, xi
        real(wp) :: dev(6), de(6)
        integer :: n
        logical :: open

        n = size(dstrain)
        de(1:n) = dstrain
        if (self%separation) then
            call close_opening(de(1:n), state(2), state(1), open)
            if (open) then
                stress = 0.0_wp
                return
            end if
        end if
        call add_elastic_trial(self, stress, de(1:n), omega)

        call mean_and_deviator(stress, m_tr, dev(1:n), tau_tr)
        p = -m_tr
        if (p <= 0.0_wp) then
            ! no contact between the grains: stress free, the shear is plastic, and with
            ! separation the volume taken beyond zero pressure is the opening
            state(1) = state(1) + tau_tr/(self%shear*sqrt3)
            if (self%separation) state(2) = state(2) + m_tr/self%bulk
            stress = 0.0_wp
            return
        end if
        if (tau_tr <= self%mu_s*p) return

        call flow_return(self, tau_tr, p, dt, tau, xi)
        stress = dev(1:n)*(tau/tau_tr)
        stress(1:3) = stress(1:3) - p
        ! |de_p| = xi / (sqrt(2) G), so d eps_q = sqrt(2/3) |de_p| = xi / (sqrt(3) G)
        state(1) = state(1) + xi/(self%shear*sqrt3)
    end subroutine mu_i_update_stress

end module mpm_material_mu_i
