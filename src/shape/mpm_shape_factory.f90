!> The registry of shape functions: the shape function a case asks for.
!>
!> One line per shape function, from its key in the case (`case%solver%shape`, an enumeration of
!> mpm_case) to its type. A key without a line here is an error, never a default.
module mpm_shape_factory
    use mpm_error, only: error_type, fatal_error, exit_other
    use mpm_strings, only: int_text
    use mpm_case, only: shape_linear, shape_cpgimp
    use mpm_shape, only: shape_type, max_nodes_per_axis
    use mpm_shape_linear, only: linear_shape_type
    use mpm_shape_gimp, only: gimp_shape_type
    implicit none
    private
    public :: new_shape

contains

    !> Allocate the shape function of key `kind`; an unknown key is an error.
    subroutine new_shape(shape, kind, error)
        class(shape_type), allocatable, intent(out) :: shape
            !! the shape function
        integer, intent(in) :: kind
            !! case%solver%shape
        type(error_type), allocatable, intent(out) :: error
            !! set (exit_other) when no shape function has the key

        if (kind == shape_linear) allocate (linear_shape_type :: shape)
        if (kind == shape_cpgimp) allocate (gimp_shape_type :: shape)
        if (.not. allocated(shape)) then
            call fatal_error(error, "no shape function has the key "//int_text(kind)// &
                " (mpm_shape_factory)", exit_other)
        else if (shape%nodes_per_axis() > max_nodes_per_axis) then
            call fatal_error(error, "shape function "//int_text(kind)//" touches "// &
                int_text(shape%nodes_per_axis())//" nodes per axis, more than the kernels' "// &
                "max_nodes_per_axis = "//int_text(max_nodes_per_axis)//" (mpm_shape)", exit_other)
        end if
    end subroutine new_shape

end module mpm_shape_factory
