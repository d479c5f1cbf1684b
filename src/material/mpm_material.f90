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

    !> Default: no state variables.
    pure integer function material_nstate(self)
        class(material_type), intent(in) :: self
            !! the material
        material_nstate = 0
    end function material_nstate

end module mpm_material
