!> The registry of shape functions: one line each in `shape_models`, and the shape function a
!> case names.
!>
!> A new shape function is one module extending `shape_type` (its width, halo, names, 1D
!> weights) and one line here. The case keeps the name of `solver.shape_function` as given
!> (mpm_case_solver); `new_shape` finds it among the names of the models, in any letter
!> case, or refuses it with the list (exit 2): the case layer lies below the shape functions
!> (they use the grid), so it cannot ask this list itself. `--check` (app/main.f90) and the
!> solver both call `new_shape`. The order of the list is the order of the names in the
!> message.
module mpm_shape_factory
    use mpm_error, only: error_type, fatal_error, exit_input, exit_other
    use mpm_strings, only: int_text, lower, quoted_list
    use mpm_shape, only: shape_type, max_nodes_per_axis, shape_name_width
    use mpm_shape_linear, only: linear_shape_type
    use mpm_shape_gimp, only: gimp_shape_type
    use mpm_shape_ugimp, only: ugimp_shape_type
    use mpm_shape_bspline2, only: bspline2_shape_type
    use mpm_shape_bspline3, only: bspline3_shape_type
    use mpm_shape_cpdi, only: cpdi_shape_type
    implicit none
    private
    public :: new_shape, shape_models, shape_choices, shape_holder_type

    !> One shape function of the registry.
    type :: shape_holder_type
        class(shape_type), allocatable :: s
            !! the shape function
    end type shape_holder_type

contains

    !> Every shape function, in the order of messages.
    pure function shape_models() result(models)
        type(shape_holder_type), allocatable :: models(:)

        allocate (models(6))
        allocate (linear_shape_type :: models(1)%s)
        allocate (gimp_shape_type :: models(2)%s)
        allocate (ugimp_shape_type :: models(3)%s)
        allocate (bspline2_shape_type :: models(4)%s)
        allocate (bspline3_shape_type :: models(5)%s)
        allocate (cpdi_shape_type :: models(6)%s)
    end function shape_models

    !> Every name solver.shape_function accepts (aliases included), in registry order.
    pure function shape_choices() result(choices)
        character(len=shape_name_width), allocatable :: choices(:)

        type(shape_holder_type), allocatable :: models(:)
        character(len=shape_name_width), allocatable :: names(:)
        integer :: m

        models = shape_models()
        allocate (choices(0))
        do m = 1, size(models)
            call models(m)%s%names(names)
            choices = [character(len=shape_name_width) :: choices, names]
        end do
    end function shape_choices

    !> Allocate the shape function named `name` (solver.shape_function of the case file
    !> `file`, any letter case); a name no shape function has is an input error (exit 2).
    subroutine new_shape(shape, name, error, file)
        class(shape_type), allocatable, intent(out) :: shape
            !! the shape function
        character(len=*), intent(in) :: name
            !! its name in the case, case%solver%shape_function
        type(error_type), allocatable, intent(out) :: error
            !! set (exit 2) when no shape function has the name
        character(len=*), intent(in) :: file
            !! the case file, for the message

        type(shape_holder_type), allocatable :: models(:)
        character(len=shape_name_width), allocatable :: names(:)
        integer :: m

        models = shape_models()
        do m = 1, size(models)
            call models(m)%s%names(names)
            if (any(names == lower(name))) then
                call move_alloc(models(m)%s, shape)
                exit
            end if
        end do
        if (.not. allocated(shape)) then
            call fatal_error(error, file//': solver.shape_function = "'//name//'" is not ' &
                //"allowed: must be one of "//quoted_list(shape_choices())//" (any letter " &
                //"case)", exit_input)
        else if (shape%nodes_per_axis() > max_nodes_per_axis) then
            call fatal_error(error, "shape function "//name//" touches "// &
                int_text(shape%nodes_per_axis())//" nodes per axis, more than the kernels' "// &
                "max_nodes_per_axis = "//int_text(max_nodes_per_axis)//" (mpm_shape)", exit_other)
        end if
    end subroutine new_shape

end module mpm_shape_factory
