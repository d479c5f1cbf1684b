!> The boundary conditions a case file may name, one line each in `boundary_models`.
!>
!> A new condition is one module extending `boundary_type` (its names, keys, reading and
!> checking, summary words and nodal action) and one line here. The order of the list is
!> the order of the names in messages ("must be one of ..."). The case's `domain` section
!> reads each face through this list (mpm_case_domain).
module mpm_boundary_registry
    use mpm_strings, only: any_same
    use mpm_boundary, only: boundary_type, boundary_holder_type, boundary_key_width
    use mpm_boundary_free, only: free_boundary_type
    use mpm_boundary_sliding, only: sliding_boundary_type
    use mpm_boundary_fixed, only: fixed_boundary_type
    use mpm_boundary_frictional, only: frictional_boundary_type
    use mpm_boundary_velocity, only: velocity_boundary_type
    use mpm_boundary_absorbing, only: absorbing_boundary_type
    use mpm_boundary_seismic, only: seismic_boundary_type
    use mpm_boundary_periodic, only: periodic_boundary_type
    implicit none
    private
    public :: boundary_models, boundary_choices, boundary_choice_codes, all_boundary_keys
    public :: boundary_allowed, names_of, keys_of

contains

    !> Every condition, with its defaults, in the order of messages.
    pure function boundary_models() result(models)
        type(boundary_holder_type), allocatable :: models(:)
            !! the conditions

        allocate (models(8))
        allocate (free_boundary_type :: models(1)%b)
        allocate (sliding_boundary_type :: models(2)%b)
        allocate (fixed_boundary_type :: models(3)%b)
        allocate (frictional_boundary_type :: models(4)%b)
        allocate (velocity_boundary_type :: models(5)%b)
        allocate (absorbing_boundary_type :: models(6)%b)
        allocate (seismic_boundary_type :: models(7)%b)
        allocate (periodic_boundary_type :: models(8)%b)
    end function boundary_models

    !> Every name a face accepts, in registry order.
    pure function boundary_choices() result(choices)
        character(len=boundary_key_width), allocatable :: choices(:)
            !! the names

        type(boundary_holder_type), allocatable :: models(:)
        integer :: m

        models = boundary_models()
        allocate (choices(0))
        do m = 1, size(models)
            choices = [character(len=boundary_key_width) :: choices, names_of(models(m)%b)]
        end do
    end function boundary_choices

    !> The registry index of each name of boundary_choices.
    pure function boundary_choice_codes() result(codes)
        integer, allocatable :: codes(:)
            !! index in boundary_models of each name

        type(boundary_holder_type), allocatable :: models(:)
        integer :: m

        models = boundary_models()
        allocate (codes(0))
        do m = 1, size(models)
            codes = [codes, spread(m, 1, size(names_of(models(m)%b)))]
        end do
    end function boundary_choice_codes

    !> The keys of a face object: "type", then those of every condition, each once, in
    !> registry order.
    pure function all_boundary_keys() result(list)
        character(len=boundary_key_width), allocatable :: list(:)
            !! the keys

        type(boundary_holder_type), allocatable :: models(:)
        character(len=boundary_key_width), allocatable :: own(:)
        integer :: m, k

        models = boundary_models()
        list = [character(len=boundary_key_width) :: "type"]
        do m = 1, size(models)
            own = keys_of(models(m)%b)
            do k = 1, size(own)
                if (.not. any_same(list, trim(own(k)))) list = [list, own(k)]
            end do
        end do
    end function all_boundary_keys

    !> What a face may be, for messages: 'one of "free", "sliding", "fixed", or an object
    !> {"type": "frictional", "mu": 0.4} for a face with Coulomb friction' (the conditions a
    !> name alone gives, then the object form of each that needs keys).
    pure function boundary_allowed() result(text)
        character(len=:), allocatable :: text
            !! the text

        type(boundary_holder_type), allocatable :: models(:)
        character(len=boundary_key_width), allocatable :: names(:)
        integer :: m, k

        models = boundary_models()
        text = "one of"
        do m = 1, size(models)
            if (len(models(m)%b%example()) > 0) cycle
            names = names_of(models(m)%b)
            do k = 1, size(names)
                text = text//' "'//trim(names(k))//'",'
            end do
        end do
        do m = 1, size(models)
            if (len(models(m)%b%example()) == 0) cycle
            text = text//" or an object "//models(m)%b%example()//" for " &
                //models(m)%b%purpose()//","
        end do
        text = text(1:len(text) - 1)
    end function boundary_allowed

    !> The names of a condition, as a function.
    pure function names_of(model) result(names)
        class(boundary_type), intent(in) :: model
            !! the condition
        character(len=boundary_key_width), allocatable :: names(:)
            !! its names, the stored one first

        call model%names(names)
    end function names_of

    !> The keys of a condition, as a function.
    pure function keys_of(model) result(keys)
        class(boundary_type), intent(in) :: model
            !! the condition
        character(len=boundary_key_width), allocatable :: keys(:)
            !! its keys besides "type"

        call model%keys(keys)
    end function keys_of

end module mpm_boundary_registry
