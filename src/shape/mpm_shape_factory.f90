!> Build the shape function a case asks for.
module mpm_shape_factory
    use mpm_case, only: shape_linear, shape_cpgimp
    use mpm_shape, only: shape_type
    use mpm_shape_linear, only: linear_shape_type
    use mpm_shape_gimp, only: gimp_shape_type
    implicit none
    private
    public :: new_shape

contains

    !> Allocate the shape function for `kind` (shape_linear or shape_cpgimp).
    subroutine new_shape(shape, kind)
        class(shape_type), allocatable, intent(out) :: shape
            !! the shape function
        integer, intent(in) :: kind
            !! case%solver%shape

        select case (kind)
        case (shape_linear)
            allocate (linear_shape_type :: shape)
        case (shape_cpgimp)
            allocate (gimp_shape_type :: shape)
        case default
            allocate (gimp_shape_type :: shape)
        end select
    end subroutine new_shape

end module mpm_shape_factory
