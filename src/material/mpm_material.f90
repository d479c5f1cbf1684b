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

end module mpm_material
