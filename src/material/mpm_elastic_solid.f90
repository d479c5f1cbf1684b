!> What every isotropic elastic solid shares: Young's modulus and Poisson's ratio (`E`, `nu`,
!> with `rho`), their Lame parameters, the P-wave speed, the stored elastic energy and the
!> summary line. The linear elastic, neo-Hookean, Mohr-Coulomb and Drucker-Prager materials
!> extend `elastic_solid_type`.
module mpm_elastic_solid
    use mpm_kinds, only: wp
    use mpm_error, only: error_type
    use mpm_strings, only: fmt_real
    use mpm_case_cursor, only: cursor_type
    use mpm_material, only: material_type, material_key_width, work_stored
    use mpm_stress, only: isotropic_elastic_energy, add_jaumann_rotation
    implicit none
    private
    public :: elastic_solid_type, elastic_keys, add_elastic_trial

    character(len=*), parameter :: elastic_keys(*) = [character(len=material_key_width) :: &
        "name", "type", "E", "nu", "rho"]
        !! keys of an elastic solid

    !> An isotropic elastic solid (the elastic part of an elasto-plastic one).
    type, abstract, extends(material_type) :: elastic_solid_type
        real(wp) :: young = 0.0_wp
            !! Young's modulus E [Pa]
        real(wp) :: poisson = 0.0_wp
            !! Poisson's ratio nu [-]
        real(wp) :: shear = 0.0_wp
            !! shear modulus G [Pa]
        real(wp) :: lame = 0.0_wp
            !! first Lame parameter lambda [Pa]
    contains
        !> `E`, `nu`, `rho` (the reading of a material with no other key).
        procedure :: read => elastic_solid_read
        !> The same, for the reading of a material with more keys.
        procedure :: read_elasticity => elastic_solid_read
        !> sqrt((K + 4G/3)/rho).
        procedure :: wave_speed => elastic_solid_wave_speed
        !> The line of E, nu, rho and c_p.
        procedure :: summary => elastic_solid_summary
        !> The same, for the summary of a material with more lines.
        procedure :: elasticity_summary => elastic_solid_summary
        !> Stored: the work of the stresses of an elastic solid.
        procedure :: work_kind => elastic_solid_work_kind
        !> 1/2 sigma : C^-1 : sigma.
        procedure :: elastic_energy_block => elastic_solid_energy_block
        !> K0 of an elastic solid confined laterally: nu / (1 - nu).
        procedure :: at_rest_ratio => elastic_solid_at_rest_ratio
        !> Set E, nu, rho and the Lame parameters.
        procedure :: set_elasticity
    end type elastic_solid_type

contains

    !> The objective elastic trial stress of a step: sigma + (Omega sigma - sigma Omega)
    !> + 2 G de + lambda tr(de) I, the elastic predictor the stress updates of
    !> mpm_material_elastic, _drucker_prager and _mu_i start with (mpm_material_mohr_coulomb
    !> writes the same lines out: with the call its 3D cases changed in the last bits).
    pure subroutine add_elastic_trial(mat, stress, de, omega)
        class(elastic_solid_type), intent(in) :: mat
            !! the material (its G and lambda)
        real(wp), intent(inout) :: stress(:)
            !! Cauchy stress, 4 (2D) or 6 (3D) components, tension positive [Pa]
        real(wp), intent(in) :: de(:)
            !! strain increment, as many components as stress [-]
        real(wp), intent(in) :: omega(3)
            !! spin increment W dt (xy, yz, zx) [-]

        call add_jaumann_rotation(stress, omega)
        stress = stress + 2.0_wp*mat%shear*de
        stress(1:3) = stress(1:3) + mat%lame*(de(1) + de(2) + de(3))
    end subroutine add_elastic_trial

    !> Set E, nu and rho, and G = E / (2 (1 + nu)), lambda = E nu / ((1 + nu)(1 - 2 nu)).
    pure subroutine set_elasticity(self, young, poisson, density)
        class(elastic_solid_type), intent(inout) :: self
            !! the material
        real(wp), intent(in) :: young
            !! Young's modulus [Pa]
        real(wp), intent(in) :: poisson
            !! Poisson's ratio [-]
        real(wp), intent(in) :: density
            !! mass density [kg/m3]

        self%young = young
        self%poisson = poisson
        self%density = density
        self%shear = young/(2.0_wp*(1.0_wp + poisson))
        self%lame = young*poisson/((1.0_wp + poisson)*(1.0_wp - 2.0_wp*poisson))
    end subroutine set_elasticity

    !> Elastic parameters of a solid: `E`, `nu`, `rho`.
    subroutine elastic_solid_read(self, item, error)
        class(elastic_solid_type), intent(inout) :: self
            !! the material
        type(cursor_type), intent(in) :: item
            !! the material object
        type(error_type), allocatable, intent(out) :: error
            !! first error found

        real(wp) :: young, poisson, density

        young = self%young
        poisson = self%poisson
        density = self%density
        call item%get_real("E", young, error, required=.true., above=0.0_wp, unit="Pa")
        if (allocated(error)) return
        call item%get_real("nu", poisson, error, required=.true., at_least=0.0_wp, &
            below=0.5_wp)
        if (allocated(error)) return
        call item%get_real("rho", density, error, required=.true., above=0.0_wp, &
            unit="kg/m3")
        if (allocated(error)) return
        call self%set_elasticity(young, poisson, density)
    end subroutine elastic_solid_read

    !> P-wave speed of an elastic solid, sqrt((K + 4G/3)/rho) [m/s].
    pure real(wp) function elastic_solid_wave_speed(self)
        class(elastic_solid_type), intent(in) :: self
            !! the material

        real(wp) :: bulk, shear

        bulk = self%young/(3.0_wp*(1.0_wp - 2.0_wp*self%poisson))
        shear = self%young/(2.0_wp*(1.0_wp + self%poisson))
        elastic_solid_wave_speed = sqrt((bulk + 4.0_wp*shear/3.0_wp)/self%density)
    end function elastic_solid_wave_speed

    !> "E = ... Pa, nu = ..., rho = ... kg/m3, c_p = ... m/s".
    pure subroutine elastic_solid_summary(self, text)
        class(elastic_solid_type), intent(in) :: self
            !! the material
        character(len=:), allocatable, intent(out) :: text
            !! the line

        text = "E = "//fmt_real(self%young)//" Pa, nu = "//fmt_real(self%poisson) &
            //", rho = "//fmt_real(self%density)//" kg/m3, c_p = " &
            //fmt_real(self%wave_speed(), 6)//" m/s"//new_line("a")
    end subroutine elastic_solid_summary

    !> Where the work of the stresses goes: stored.
    pure integer function elastic_solid_work_kind(self)
        class(elastic_solid_type), intent(in) :: self
            !! the material

        elastic_solid_work_kind = work_stored
    end function elastic_solid_work_kind

    !> K0 of an elastic solid loaded by its weight under lateral confinement (no horizontal
    !> strain): nu / (1 - nu).
    pure real(wp) function elastic_solid_at_rest_ratio(self)
        class(elastic_solid_type), intent(in) :: self
            !! the material

        elastic_solid_at_rest_ratio = self%poisson/(1.0_wp - self%poisson)
    end function elastic_solid_at_rest_ratio

    !> Stored elastic energy per unit volume, 1/2 sigma : C^-1 : sigma (isotropic elasticity
    !> of E and nu; in an elasto-plastic solid the stress is elastic, the plastic strain holds
    !> no energy).
    pure subroutine elastic_solid_energy_block(self, n, stress, state, density)
        class(elastic_solid_type), intent(in) :: self
            !! the material
        integer, intent(in) :: n
            !! particles in the block
        real(wp), intent(in) :: stress(:, :)
            !! Cauchy stresses [Pa]
        real(wp), intent(in) :: state(:, :)
            !! material states (unused)
        real(wp), intent(out) :: density(:)
            !! stored elastic energy per unit volume [J/m3]

        integer :: j

        do j = 1, n
            density(j) = isotropic_elastic_energy(stress(:, j), self%young, self%poisson)
        end do
    end subroutine elastic_solid_energy_block

end module mpm_elastic_solid
