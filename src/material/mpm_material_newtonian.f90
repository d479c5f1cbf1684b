!> Compressible Newtonian fluid: sigma = -p I + 2 mu dev(D), pressure from a bulk modulus.
!>
!> The pressure is carried in the stress (tension positive, p = -tr(sigma)/3) and updated in
!> rate form, p_{n+1} = p_n - K tr(d eps); the viscous stress is recomputed every step from the
!> rate of deformation D = d eps / dt. No state variables.
!>
!> Objectivity needs no Jaumann term: the viscous part depends only on the current D, which is
!> itself objective, and keeps no history to rotate; the pressure part -p I is isotropic, so a
!> rotation leaves it unchanged (Omega (p I) - (p I) Omega = 0), and the trace of the stress,
!> from which p_n is read, is invariant under rotation. The viscous part of the previous step
!> is dropped because it is deviatoric and p_n is read from the trace only.
!>
!> `materials[i].type = "newtonian"`, keys `rho`, `viscosity`, `bulk_modulus`.
module mpm_material_newtonian
    use mpm_kinds, only: wp
    use mpm_error, only: error_type
    use mpm_strings, only: fmt_real
    use mpm_case_cursor, only: cursor_type
    use mpm_material, only: material_type, material_key_width, work_viscous
    implicit none
    private
    public :: newtonian_material_type, new_newtonian_material

    !> Newtonian fluid with a linear pressure-volume law.
    type, extends(material_type) :: newtonian_material_type
        real(wp) :: viscosity = 0.0_wp
            !! dynamic viscosity mu [Pa s]
        real(wp) :: bulk_modulus = 0.0_wp
            !! bulk modulus K [Pa]
    contains
        procedure, nopass :: names => newtonian_names
        procedure, nopass :: keys => newtonian_keys
        procedure :: read => newtonian_read
        procedure :: wave_speed => newtonian_wave_speed
            !! sqrt(K/rho)
        procedure :: time_step_limit => newtonian_time_step_limit
            !! the stable step of explicit viscous diffusion
        procedure :: summary => newtonian_summary
        procedure :: update_stress => newtonian_update_stress
            !! pressure in rate form plus the viscous stress of the step's strain rate
        procedure :: work_kind => newtonian_work_kind
            !! viscous: the work beyond the stored compression energy is dissipated
        procedure :: elastic_energy_block => newtonian_elastic_energy_block
            !! p^2 / (2 K)
    end type newtonian_material_type

contains

    !> Names accepted for `type`.
    pure subroutine newtonian_names(list)
        character(len=material_key_width), allocatable, intent(out) :: list(:)
            !! the names

        list = [character(len=material_key_width) :: "newtonian"]
    end subroutine newtonian_names

    !> Keys of a Newtonian fluid.
    pure subroutine newtonian_keys(list)
        character(len=material_key_width), allocatable, intent(out) :: list(:)
            !! the keys

        list = [character(len=material_key_width) :: "name", "type", "rho", "viscosity", &
            "bulk_modulus"]
    end subroutine newtonian_keys

    !> A Newtonian fluid: `rho`, `viscosity`, `bulk_modulus`.
    subroutine newtonian_read(self, item, error)
        class(newtonian_material_type), intent(inout) :: self
            !! the material
        type(cursor_type), intent(in) :: item
            !! the material object ("materials[i]")
        type(error_type), allocatable, intent(out) :: error
            !! first error found

        call item%get_real("rho", self%density, error, required=.true., above=0.0_wp, &
            unit="kg/m3")
        if (allocated(error)) return
        call item%get_real("viscosity", self%viscosity, error, required=.true., &
            at_least=0.0_wp, unit="Pa s")
        if (allocated(error)) return
        call item%get_real("bulk_modulus", self%bulk_modulus, error, required=.true., &
            above=0.0_wp, unit="Pa")
    end subroutine newtonian_read

    !> Construct a Newtonian fluid from mu, K and rho.
    pure subroutine new_newtonian_material(mat, name, viscosity, bulk_modulus, density)
        type(newtonian_material_type), intent(out) :: mat
            !! the material
        character(len=*), intent(in) :: name
            !! material name
        real(wp), intent(in) :: viscosity
            !! dynamic viscosity [Pa s]
        real(wp), intent(in) :: bulk_modulus
            !! bulk modulus [Pa]
        real(wp), intent(in) :: density
            !! mass density [kg/m3]

        mat%name = name
        mat%density = density
        mat%viscosity = viscosity
        mat%bulk_modulus = bulk_modulus
    end subroutine new_newtonian_material

    !> P-wave speed of the fluid, sqrt(K/rho) [m/s].
    pure real(wp) function newtonian_wave_speed(self)
        class(newtonian_material_type), intent(in) :: self
            !! the material

        newtonian_wave_speed = sqrt(self%bulk_modulus/self%density)
    end function newtonian_wave_speed

    !> Stable time step of explicit viscous diffusion, rho dx^2 / (2 dim mu) [s]; huge
    !> without viscosity.
    pure real(wp) function newtonian_time_step_limit(self, dx, dim)
        class(newtonian_material_type), intent(in) :: self
            !! the material
        real(wp), intent(in) :: dx
            !! cell size [m]
        integer, intent(in) :: dim
            !! space dimensions

        if (self%viscosity > 0.0_wp) then
            newtonian_time_step_limit = self%density*dx*dx/(2.0_wp*real(dim, wp)*self%viscosity)
        else
            newtonian_time_step_limit = huge(1.0_wp)
        end if
    end function newtonian_time_step_limit

    !> "rho = ... kg/m3, viscosity = ... Pa s, bulk modulus = ... Pa, c_p = ... m/s".
    pure subroutine newtonian_summary(self, text)
        class(newtonian_material_type), intent(in) :: self
            !! the material
        character(len=:), allocatable, intent(out) :: text
            !! the line

        text = "rho = "//fmt_real(self%density)//" kg/m3, viscosity = " &
            //fmt_real(self%viscosity)//" Pa s, bulk modulus = "//fmt_real(self%bulk_modulus) &
            //" Pa, c_p = "//fmt_real(self%wave_speed(), 6)//" m/s"//new_line("a")
    end subroutine newtonian_summary

    !> The work of the viscous stresses is dissipated.
    pure integer function newtonian_work_kind(self)
        class(newtonian_material_type), intent(in) :: self
            !! the material
        newtonian_work_kind = work_viscous
    end function newtonian_work_kind

    !> Stored (compression) energy per unit volume, p^2 / (2 K), p = -tr(sigma)/3: the
    !> pressure is elastic, the deviatoric stress viscous.
    pure subroutine newtonian_elastic_energy_block(self, n, stress, state, density)
        class(newtonian_material_type), intent(in) :: self
            !! the material
        integer, intent(in) :: n
            !! particles in the block
        real(wp), intent(in) :: stress(:, :)
            !! Cauchy stresses [Pa]
        real(wp), intent(in) :: state(:, :)
            !! unused
        real(wp), intent(out) :: density(:)
            !! stored energy per unit volume [J/m3]

        integer :: j
        real(wp) :: pressure

        do j = 1, n
            pressure = -(stress(1, j) + stress(2, j) + stress(3, j))/3.0_wp
            density(j) = pressure*pressure/(2.0_wp*self%bulk_modulus)
        end do
    end subroutine newtonian_elastic_energy_block

    !> sigma_{n+1} = -p_{n+1} I + 2 mu dev(D), p_{n+1} = -tr(sigma_n)/3 - K tr(d eps),
    !> D = d eps / dt. Plane strain (4 components): D_zz = 0, so
    !> sigma_zz = -p + 2 mu (0 - tr(D)/3). With dt <= 0 only the pressure is updated.
    pure subroutine newtonian_update_stress(self, stress, dstrain, omega, dt, state)
        class(newtonian_material_type), intent(in) :: self
            !! the material
        real(wp), intent(inout) :: stress(:)
            !! Cauchy stress, 4 (2D) or 6 (3D) components, tension positive [Pa]
        real(wp), intent(in) :: dstrain(:)
            !! strain increment D dt, tensor components [-]
        real(wp), intent(in) :: omega(3)
            !! spin increment (unused: see the module notes on objectivity) [-]
        real(wp), intent(in) :: dt
            !! time step [s]
        real(wp), intent(inout) :: state(:)
            !! unused (no state variables)

        real(wp) :: pressure, dvol, de(size(dstrain))

        de = dstrain
        if (size(de) == 4) de(3) = 0.0_wp
        dvol = de(1) + de(2) + de(3)
        pressure = -(stress(1) + stress(2) + stress(3))/3.0_wp - self%bulk_modulus*dvol
        if (dt > 0.0_wp) then
            de(1:3) = de(1:3) - dvol/3.0_wp
            stress = (2.0_wp*self%viscosity/dt)*de
        else
            stress = 0.0_wp
        end if
        stress(1:3) = stress(1:3) - pressure
    end subroutine newtonian_update_stress

end module mpm_material_newtonian
