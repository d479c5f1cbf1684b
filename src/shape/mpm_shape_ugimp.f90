!> Uniform GIMP (uGIMP) shape functions: the cpGIMP weights of mpm_shape_gimp with the
!> particle domain kept at its initial size (lp = lp0, Bardenhagen & Kober 2004), whatever
!> the deformation. The weights are those of the cpGIMP formulas (truncated at the grid
!> ends in the same way); only the half-size they are given differs (`initial_domain`:
!> mpm_stencil passes particles%lp0). The contact gaps of the frictional faces still take
!> the deformed domain (mpm_particle_domain::domain_half_sizes of F).
module mpm_shape_ugimp
    use mpm_shape, only: shape_name_width
    use mpm_shape_gimp, only: gimp_shape_type
    implicit none
    private
    public :: ugimp_shape_type

    !> uGIMP: cpGIMP on the initial particle domain (3 nodes per direction).
    type, extends(gimp_shape_type) :: ugimp_shape_type
    contains
        procedure :: names => ugimp_names
        procedure :: initial_domain => ugimp_initial_domain
    end type ugimp_shape_type

contains

    pure subroutine ugimp_names(self, names)
        class(ugimp_shape_type), intent(in) :: self
        character(len=shape_name_width), allocatable, intent(out) :: names(:)
        names = [character(len=shape_name_width) :: "ugimp"]
    end subroutine ugimp_names

    !> The weights take the initial particle domain, lp0.
    pure logical function ugimp_initial_domain(self)
        class(ugimp_shape_type), intent(in) :: self
        ugimp_initial_domain = .true.
    end function ugimp_initial_domain

end module mpm_shape_ugimp
