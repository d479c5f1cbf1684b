!> Material registry: every type name belongs to one material, every material's keys hold
!> "name" and "type" once, the choice codes point at the material of each name, and each
!> material read from a small object of the case file has a finite positive wave speed, a
!> summary of whole lines and keys of its inner objects under its own keys.
program test_mpm_material_registry
    use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
    use mpm_kinds, only: wp
    use mpm_error, only: error_type
    use mpm_strings, only: any_same
    use mpm_json, only: json_document_type, json_parse_string, json_root, json_free
    use mpm_case_cursor, only: cursor_type, new_cursor
    use mpm_material, only: material_type, material_holder_type, material_key_width, &
        key_path_width
    use mpm_material_registry, only: material_models, material_choices, material_choice_codes, &
        all_material_keys, names_of, keys_of
    use mpm_testing, only: test_suite_type, new_suite, check, finish
    implicit none

    type(test_suite_type) :: suite

    call new_suite(suite, "mpm_material_registry")
    call check_names_and_keys()
    call check_read_materials()
    call finish(suite)

contains

    !> Names unique over the registry, keys unique per material, codes consistent.
    subroutine check_names_and_keys()
        type(material_holder_type), allocatable :: models(:)
        character(len=material_key_width), allocatable :: choices(:), keys(:), names(:)
        integer, allocatable :: codes(:)
        integer :: i, m, k
        logical :: unique

        models = material_models()
        choices = material_choices()
        codes = material_choice_codes()
        call check(suite, size(codes) == size(choices), "one code per type name")
        unique = .true.
        do i = 2, size(choices)
            if (any_same(choices(1:i - 1), trim(choices(i)))) unique = .false.
        end do
        call check(suite, unique, "each type name belongs to one material")
        do i = 1, size(choices)
            names = names_of(models(codes(i))%m)
            call check(suite, any_same(names, trim(choices(i))), &
                trim(choices(i))//": its code points at its material")
        end do
        do m = 1, size(models)
            keys = keys_of(models(m)%m)
            names = names_of(models(m)%m)
            call check(suite, any_same(keys, "name") .and. any_same(keys, "type"), &
                trim(names(1))//": keys hold name and type")
            unique = .true.
            do k = 2, size(keys)
                if (any_same(keys(1:k - 1), trim(keys(k)))) unique = .false.
            end do
            call check(suite, unique, trim(names(1))//": each key once")
            call check(suite, all([(any_same(all_material_keys(), trim(keys(k))), &
                k = 1, size(keys))]), trim(names(1))//": keys in all_material_keys")
        end do
    end subroutine check_names_and_keys

    !> Each material read from a small valid object (the materials of this build without
    !> an example below are only checked by check_names_and_keys).
    subroutine check_read_materials()
        type(material_holder_type), allocatable :: models(:)
        character(len=material_key_width), allocatable :: names(:)
        character(len=:), allocatable :: example, text
        character(len=key_path_width), allocatable :: sections(:)
        class(material_type), allocatable :: law
        type(json_document_type) :: doc
        type(error_type), allocatable :: error
        type(cursor_type) :: item
        real(wp) :: speed
        integer :: m, k
        logical :: inside

        models = material_models()
        do m = 1, size(models)
            names = names_of(models(m)%m)
            select case (trim(names(1)))
            case ("linear_elastic", "neo_hookean")
                example = '{"E": 1e6, "nu": 0.3, "rho": 1000}'
            case ("mohr_coulomb", "drucker_prager")
                example = '{"E": 1e6, "nu": 0.3, "rho": 1000, "phi": 30, "c": 100}'
            case ("newtonian")
                example = '{"rho": 1000, "viscosity": 1e-3, "bulk_modulus": 2.2e9}'
            case ("tresca")
                example = '{"E": 1e6, "nu": 0.49, "rho": 1000, "Su": 1e4, "Su_gradient": 1e3, ' &
                    //'"Su_elevation": 5, "softening": {"type": "linear", "sensitivity": 2, ' &
                    //'"strain": 0.2}}'
            case ("rigid")
                example = '{"rho": 1000}'
            case ("cam_clay")
                example = '{"M": 1.2, "lambda": 0.2, "kappa": 0.04, "e0": 1.0, "nu": 0.3, ' &
                    //'"rho": 1000, "OCR": 2, "p_min": 500}'
            case ("mu_i")
                example = '{"K": 1e6, "G": 5e5, "rho": 1000, "mu_s": 0.38, "mu_2": 0.64, ' &
                    //'"I_0": 0.279, "grain_diameter": 5e-4, "grain_density": 2450}'
            case default
                cycle
            end select
            call json_parse_string(example, doc, error, "example")
            call check(suite, .not. allocated(error), trim(names(1))//": example parses")
            if (allocated(error)) cycle
            item = new_cursor(json_root(doc), "materials[1]", "example")
            allocate (law, source=models(m)%m)
            call law%read(item, error)
            call json_free(doc)
            call check(suite, .not. allocated(error), trim(names(1))//": example reads")
            if (.not. allocated(error)) then
                speed = law%wave_speed()
                ! (a rigid body carries no wave: zero)
                call check(suite, ieee_is_finite(speed) .and. (speed > 0.0_wp .or. &
                    (law%rigid() .and. speed == 0.0_wp)), trim(names(1))//": finite positive " &
                    //"wave speed (zero: rigid)")
                call check(suite, law%density == 1000.0_wp, trim(names(1))//": density read")
                call check(suite, law%time_step_limit(0.1_wp, 2) > 0.0_wp, &
                    trim(names(1))//": positive time-step limit")
                call check(suite, law%nstate() >= 0, trim(names(1))//": nstate >= 0")
                call law%summary(text)
                call check(suite, len(text) > 1, trim(names(1))//": summary lines")
                if (len(text) > 0) call check(suite, text(len(text):) == new_line("a"), &
                    trim(names(1))//": summary of whole lines")
                call law%section_keys(sections)
                inside = .true.
                do k = 1, size(sections)
                    inside = inside .and. any_same(keys_of(law), &
                        sections(k)(1:index(sections(k), ".") - 1))
                end do
                call check(suite, inside, trim(names(1))//": inner keys under its own keys")
            end if
            deallocate (law)
        end do
    end subroutine check_read_materials

end program test_mpm_material_registry
