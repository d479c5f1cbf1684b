!> The material models a case file may name, one line each in `material_models`.
!>
!> A new model is a module extending material_model_type (its names, keys, reading, wave speed,
!> time-step limit and state) and one line here. The order of the list is the order of the
!> names in messages ("must be one of ...") and of the key paths of case_key_paths.
module mpm_case_material_registry
    use mpm_kinds, only: wp
    use mpm_strings, only: same, any_same
    use mpm_case_material_model, only: material_model_type, material_spec_type, key_width, &
        elastic_wave_speed
    use mpm_case_material_elastic, only: elastic_model_type
    use mpm_case_material_mohr_coulomb, only: mohr_coulomb_model_type
    use mpm_case_material_drucker_prager, only: drucker_prager_model_type
    use mpm_case_material_newtonian, only: newtonian_model_type
    use mpm_case_material_neo_hookean, only: neo_hookean_model_type
    implicit none
    private
    public :: material_model_entry_type, material_models, material_model_of
    public :: material_choices, material_choice_codes, all_material_keys
    public :: material_wave_speed, material_time_step_limit, writes_plastic_strain
    public :: names_of, keys_of

    !> One model of the registry.
    type :: material_model_entry_type
        class(material_model_type), allocatable :: model
            !! the model
    end type material_model_entry_type

contains

    !> Every material model, in the order of messages and key paths.
    pure function material_models() result(models)
        type(material_model_entry_type), allocatable :: models(:)
            !! the models

        allocate (models(5))
        allocate (models(1)%model, source=elastic_model_type())
        allocate (models(2)%model, source=mohr_coulomb_model_type())
        allocate (models(3)%model, source=drucker_prager_model_type())
        allocate (models(4)%model, source=newtonian_model_type())
        allocate (models(5)%model, source=neo_hookean_model_type())
    end function material_models

    !> Index in material_models of the model a material is of (its stored name), 0 when none
    !> (a material made in code without a type).
    pure integer function material_model_of(mat)
        type(material_spec_type), intent(in) :: mat
            !! resolved material

        type(material_model_entry_type), allocatable :: models(:)
        character(len=key_width), allocatable :: names(:)

        material_model_of = 0
        if (.not. allocated(mat%type)) return
        models = material_models()
        do material_model_of = 1, size(models)
            names = names_of(models(material_model_of)%model)
            if (same(trim(names(1)), mat%type)) return
        end do
        material_model_of = 0
    end function material_model_of

    !> Every name `materials[i].type` accepts (aliases included), in registry order.
    pure function material_choices() result(choices)
        character(len=key_width), allocatable :: choices(:)
            !! the names

        type(material_model_entry_type), allocatable :: models(:)
        integer :: m

        models = material_models()
        allocate (choices(0))
        do m = 1, size(models)
            choices = [character(len=key_width) :: choices, names_of(models(m)%model)]
        end do
    end function material_choices

    !> The registry index of each name of material_choices.
    pure function material_choice_codes() result(codes)
        integer, allocatable :: codes(:)
            !! index in material_models of each name

        type(material_model_entry_type), allocatable :: models(:)
        integer :: m

        models = material_models()
        allocate (codes(0))
        do m = 1, size(models)
            codes = [codes, spread(m, 1, size(names_of(models(m)%model)))]
        end do
    end function material_choice_codes

    !> The keys of every model, each once, in registry order: a key of another model is
    !> reported as misplaced rather than misspelt.
    pure function all_material_keys() result(list)
        character(len=key_width), allocatable :: list(:)
            !! the keys

        type(material_model_entry_type), allocatable :: models(:)
        character(len=key_width), allocatable :: own(:)
        integer :: m, k

        models = material_models()
        allocate (list(0))
        do m = 1, size(models)
            own = keys_of(models(m)%model)
            do k = 1, size(own)
                if (.not. any_same(list, trim(own(k)))) list = [list, own(k)]
            end do
        end do
    end function all_material_keys

    !> P-wave speed of a material, from its model (an elastic solid's without a model) [m/s].
    pure real(wp) function material_wave_speed(mat)
        type(material_spec_type), intent(in) :: mat
            !! resolved material

        type(material_model_entry_type), allocatable :: models(:)
        integer :: m

        m = material_model_of(mat)
        if (m == 0) then
            material_wave_speed = elastic_wave_speed(mat)
            return
        end if
        models = material_models()
        material_wave_speed = models(m)%model%wave_speed(mat)
    end function material_wave_speed

    !> Time-step limit of a material besides the CFL condition, from its model (huge without
    !> a model) [s].
    pure real(wp) function material_time_step_limit(mat, dx, dim)
        type(material_spec_type), intent(in) :: mat
            !! resolved material
        real(wp), intent(in) :: dx
            !! cell size [m]
        integer, intent(in) :: dim
            !! space dimensions

        type(material_model_entry_type), allocatable :: models(:)
        integer :: m

        material_time_step_limit = huge(1.0_wp)
        m = material_model_of(mat)
        if (m == 0) return
        models = material_models()
        material_time_step_limit = models(m)%model%time_step_limit(mat, dx, dim)
    end function material_time_step_limit

    !> Whether a material writes the plastic strain (its model's state).
    pure logical function writes_plastic_strain(mat)
        type(material_spec_type), intent(in) :: mat
            !! resolved material

        type(material_model_entry_type), allocatable :: models(:)
        integer :: m

        writes_plastic_strain = .false.
        m = material_model_of(mat)
        if (m == 0) return
        models = material_models()
        writes_plastic_strain = models(m)%model%writes_plastic_strain()
    end function writes_plastic_strain

    !> The names of a model, as a function.
    pure function names_of(model) result(names)
        class(material_model_type), intent(in) :: model
            !! the model
        character(len=key_width), allocatable :: names(:)
            !! its names, the stored one first

        call model%names(names)
    end function names_of

    !> The keys of a model, as a function.
    pure function keys_of(model) result(keys)
        class(material_model_type), intent(in) :: model
            !! the model
        character(len=key_width), allocatable :: keys(:)
            !! its keys

        call model%keys(keys)
    end function keys_of

end module mpm_case_material_registry
