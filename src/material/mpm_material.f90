!> The abstract material: a constitutive model that updates the stress of one particle.
!>
!> A new material is a new module with an extension of `material_type`; the solver calls
!> only its bindings. Stress conventions are those of `mpm_stress`. The time step limits of a
!> material (wave speed, viscosity) are computed from its specification in `mpm_case`, the one
!> place the case reader and the solver both use.
module mpm_material
    use mpm_kinds, only: wp
    implicit none
    private
    public :: material_type, material_holder_type
    public :: work_stored, work_plastic, work_viscous, nwork_kinds

    integer, parameter :: work_stored = 1, work_plastic = 2, work_viscous = 3
        !! where the work of the stresses goes, beyond the elastic energy the stress stores:
        !! nowhere (an elastic material: every joule is stored), plastic dissipation, viscous
        !! dissipation (`work_kind`)
    integer, parameter :: nwork_kinds = 3
        !! number of work kinds

    !> A constitutive model with its parameters.
    type, abstract :: material_type
        character(len=:), allocatable :: name
            !! name given in the case file
        real(wp) :: density = 0.0_wp
            !! initial mass density [kg/m3]
    contains
        procedure(update_stress_interface), deferred :: update_stress
            !! stress update of one particle over one step
        procedure :: nstate => material_nstate
            !! number of state variables per particle (default 0)
        procedure :: update_stress_block => material_update_stress_block
            !! update_stress of a block of particles (default: one by one); a material whose
            !! update is a few operations overrides it with a loop over the block
        procedure :: work_kind => material_work_kind
            !! where the work of the stresses goes besides the stored elastic energy
            !! (`work_stored`, `work_plastic`, `work_viscous`; default plastic)
        procedure :: elastic_energy_block => material_elastic_energy_block
            !! stored elastic energy per unit volume of a block of particles (default 0: all
            !! the work of the stresses is dissipated)
    end type material_type

    !> Holder so that materials of different types fit in one array.
    type :: material_holder_type
        class(material_type), allocatable :: m
            !! the material
    end type material_holder_type

    abstract interface
        !> Update the stress of one particle for a strain and a spin increment (objective).
        pure subroutine update_stress_interface(self, stress, dstrain, omega, dt, state)
            import :: material_type, wp
            class(material_type), intent(in) :: self
                !! the material
            real(wp), intent(inout) :: stress(:)
                !! Cauchy stress, 4 (2D) or 6 (3D) components, tension positive [Pa]
            real(wp), intent(in) :: dstrain(:)
                !! strain increment D dt, tensor components, same size as stress [-]
            real(wp), intent(in) :: omega(3)
                !! spin increment W dt (xy, yz, zx) [-]
            real(wp), intent(in) :: dt
                !! time step [s] (rate-dependent materials)
            real(wp), intent(inout) :: state(:)
                !! material state of the particle, at least nstate() values (may be larger
                !! when the case mixes materials; use only the first nstate())
        end subroutine update_stress_interface
    end interface

contains

    !> Stress update of n particles of this material over one step: update_stress of each.
    pure subroutine material_update_stress_block(self, n, stress, dstrain, omega, dt, state)
        class(material_type), intent(in) :: self
            !! the material
        integer, intent(in) :: n
            !! particles in the block
        real(wp), intent(inout) :: stress(:, :)
            !! Cauchy stresses (4 or 6, at least n), tension positive [Pa]
        real(wp), intent(in) :: dstrain(:, :)
            !! strain increments D dt (tensor components, as stress) [-]
        real(wp), intent(in) :: omega(:, :)
            !! spin increments W dt (xy, yz, zx; 3, at least n) [-]
        real(wp), intent(in) :: dt
            !! time step [s]
        real(wp), intent(inout) :: state(:, :)
            !! material states (at least nstate(), at least n)

        integer :: j

        do j = 1, n
            call self%update_stress(stress(:, j), dstrain(:, j), omega(:, j), dt, state(:, j))
        end do
    end subroutine material_update_stress_block

    !> Default: no state variables.
    pure integer function material_nstate(self)
        class(material_type), intent(in) :: self
            !! the material
        material_nstate = 0
    end function material_nstate

    !> Default: the work of the stresses is dissipated (plastic), nothing is stored.
    pure integer function material_work_kind(self)
        class(material_type), intent(in) :: self
            !! the material
        material_work_kind = work_plastic
    end function material_work_kind

    !> Stored elastic energy per unit (current) volume of n particles; default 0.
    pure subroutine material_elastic_energy_block(self, n, stress, state, density)
        class(material_type), intent(in) :: self
            !! the material
        integer, intent(in) :: n
            !! particles in the block
        real(wp), intent(in) :: stress(:, :)
            !! Cauchy stresses (4 or 6, at least n), tension positive [Pa]
        real(wp), intent(in) :: state(:, :)
            !! material states (at least nstate(), at least n)
        real(wp), intent(out) :: density(:)
            !! stored elastic energy per unit volume (at least n) [J/m3]

        density(1:n) = 0.0_wp
    end subroutine material_elastic_energy_block

end module mpm_material
